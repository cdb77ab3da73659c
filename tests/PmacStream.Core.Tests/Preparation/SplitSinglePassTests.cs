using System.Text.Json;
using System.Text.Json.Serialization;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>The checker in the splitter's own pass, the ordered hand-over between its threads, the streamed manifest.</summary>
public class SplitSinglePassTests
{
    private static string Moves(int from, int count) =>
        string.Concat(Enumerable.Range(from, count).Select(i => $"N{i} G01 X{i}.25 Y-{i % 7}.5 F{100 + (i % 3)}\n"));

    [Fact]
    public void Checker_errors_found_late_refuse_the_split_listing_line_and_column_and_leave_no_folder()
    {
        // Lexically clean (the splitter alone would split it); the checker finds an unknown G code and a letter the
        // profile does not use, thousands of lines in, after chunks were already written into the hidden folder.
        var text = "O1\n" + Moves(2, 4000) + "N4002 G05 X2\n" + Moves(4003, 3000) + "N7003 G00 X1 Q5\nM30\n";
        using var tp = new TempProgram(text);
        var written = 0;
        var act = () => tp.Split(new SplitOptions { CheckProfile = MachineProfile.Paper, BlocksPerChunk = 100, AfterChunkWritten = _ => written++ });
        var e = act.Should().Throw<SplitException>().Which;
        e.FromChecker.Should().BeTrue();
        e.ErrorCount.Should().Be(2);
        e.Diagnostics.Select(d => (d.Code, d.Line, d.Column)).Should().Equal(
            (DiagnosticCodes.UnknownGCode, 4002, 7), (DiagnosticCodes.UnsupportedLetter, 7003, 14));
        e.Message.Should().Contain("2 error(s); not split");
        written.Should().BeGreaterThan(0, "chunks before the first error were written to the hidden folder, then deleted");
        Directory.GetFileSystemEntries(tp.Folder).Should().Equal(tp.SourcePath);

        var plain = tp.Split(new SplitOptions { BlocksPerChunk = 100 });
        plain.Manifest.TotalBlocks.Should().Be(7003, "without the checker only lexical errors refuse");
    }

    [Fact]
    public void Force_skips_the_checker_and_splits()
    {
        using var tp = new TempProgram("O1\nG01 X1 F100\nG05 X2\nM30\n");
        var r = tp.Split(new SplitOptions { CheckProfile = MachineProfile.Default, AllowErrors = true, ProgramTail = "" });
        r.Manifest.TotalBlocks.Should().Be(3);
    }

    [Fact]
    public void Lexical_errors_are_reported_by_the_checker_once_with_their_columns()
    {
        using var tp = new TempProgram("O1\nG01 X1 F100\nG01 X1#2\nG01 Y2..5\nM30\n");
        var act = () => tp.Split(new SplitOptions { CheckProfile = MachineProfile.Default });
        var e = act.Should().Throw<SplitException>().Which;
        e.FromChecker.Should().BeTrue();
        e.Diagnostics.Select(d => (d.Code, d.Line, d.Column)).Should().Equal(
            (DiagnosticCodes.IllegalCharacter, 3, 7), (DiagnosticCodes.MalformedNumber, 4, 5));
        Directory.GetFileSystemEntries(tp.Folder).Should().Equal(tp.SourcePath);
    }

    [Fact]
    public void Checked_and_unchecked_passes_write_the_same_chunks()
    {
        var demo = RepoRoot.DemoProgram;
        using var a = new TempProgram(File.ReadAllBytes(demo), "demo.nc");
        using var b = new TempProgram(File.ReadAllBytes(demo), "demo.nc");
        var checkedRun = a.Split(new SplitOptions { CheckProfile = MachineProfile.Default, BlocksPerChunk = 97 });
        // Forced, the checker does not run, but the host's conversions do (with their own interpreter).
        var plainRun = b.Split(new SplitOptions { CheckProfile = MachineProfile.Default, AllowErrors = true, BlocksPerChunk = 97 });
        checkedRun.Manifest.Chunks.Select(c => (c.FileName, c.Sha256, c.FirstSourceLine, c.LastSourceLine))
            .Should().Equal(plainRun.Manifest.Chunks.Select(c => (c.FileName, c.Sha256, c.FirstSourceLine, c.LastSourceLine)));
        checkedRun.Manifest.Chunks.Should().HaveCountGreaterThan(10);
    }

    [Fact]
    public void Many_batches_and_a_line_larger_than_a_batch_keep_every_block_in_order()
    {
        // Crosses the hand-over's batch limits many times (lines and bytes) and makes one batch grow for a huge line.
        var text = TestPrograms.Text(string.Empty, 9000, i => i == 4321 ? $"G01 X{i} ({new string('c', 200_000)})" : $"G01 X{i}", footer: string.Empty);
        using var tp = new TempProgram(text);
        var o = new SplitOptions { ProgramTail = "", BlocksPerChunk = 333 };
        var r = tp.Split(o);
        var body = ChunkText.Body(r, o);
        body.Should().Equal(Enumerable.Range(1, 9000).Select(i => $"M0=={i} G01 X{i} F(P500)"));
        r.Manifest.Chunks.Select(c => c.FirstSourceLine).Should().BeInAscendingOrder();
    }

    [Fact]
    public void Hand_over_keeps_order_exactly_under_random_timing()
    {
        var rnd = new Random(4);
        var delays = Enumerable.Range(0, 3000).Select(_ => rnd.Next(0, 20) == 0).ToArray();
        using var q = new HandOff<int>(3, CancellationToken.None);
        var producer = new Thread(() =>
        {
            for (var i = 0; i < delays.Length; i++)
            {
                if (delays[i])
                {
                    Thread.Sleep(1);
                }

                q.Add(i);
            }

            q.Complete();
        });
        producer.Start();
        var got = new List<int>();
        while (q.TryTake(out var item))
        {
            if (delays[(item * 7) % delays.Length])
            {
                Thread.Sleep(1);
            }

            got.Add(item);
        }

        producer.Join();
        got.Should().Equal(Enumerable.Range(0, delays.Length));
    }

    [Fact]
    public void Hand_over_wakes_a_blocked_side_on_cancellation()
    {
        using var cts = new CancellationTokenSource();
        using var q = new HandOff<int>(1, cts.Token);
        q.Add(1);
        Exception? failure = null;
        var blocked = new Thread(() =>
        {
            try
            {
                q.Add(2);
            }
            catch (Exception e)
            {
                failure = e;
            }
        });
        blocked.Start();
        blocked.Join(50).Should().BeFalse("the queue is full");
        cts.Cancel();
        blocked.Join(TimeSpan.FromSeconds(10)).Should().BeTrue();
        failure.Should().BeOfType<OperationCanceledException>();
    }

    [Fact]
    public void Streamed_manifest_is_byte_identical_to_the_serializer_and_loads_back()
    {
        using var tp = new TempProgram("G01 X1\nG01 X2\nG41.2 D1 X0\nM41 T2\nG01 X3\n", "零件 \"q\".nc");
        var r = tp.Split(new SplitOptions { BlocksPerChunk = 1, CheckProfile = MachineProfile.Default, AllowErrors = true });
        r.Manifest.NotYetCodes.Should().Equal(new Dictionary<string, int> { ["G41.2"] = 3, ["M41"] = 4 });
        var streamed = File.ReadAllBytes(r.ManifestPath);
        var options = new JsonSerializerOptions
        {
            WriteIndented = true,
            PropertyNamingPolicy = JsonNamingPolicy.CamelCase,
            Converters = { new JsonStringEnumConverter(JsonNamingPolicy.CamelCase) },
        };
        var records = r.Manifest with { Chunks = r.Manifest.Chunks.ToList() };
        streamed.Should().Equal(JsonSerializer.SerializeToUtf8Bytes(records, options));
        var withNullTail = records with { Shape = null, Feed = FeedMode.Override, Tracking = TrackingPlacement.Paper };
        using var ms = new MemoryStream();
        withNullTail.WriteTo(ms);
        ms.ToArray().Should().Equal(JsonSerializer.SerializeToUtf8Bytes(withNullTail, options));
        ChunkManifest.Load(r.ManifestPath).Chunks.Should().Equal(r.Manifest.Chunks);
    }
}
