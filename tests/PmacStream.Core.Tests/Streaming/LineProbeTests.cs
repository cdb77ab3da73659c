using PmacStream.Pmac;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Streaming;

/// <summary>Delivers the first <see cref="Cut"/> lines of download number <see cref="OnCall"/>, then drops the link once.</summary>
internal sealed class CutOnceConnection(IPmacPortEndpoint port) : IPmacConnection
{
    private readonly InProcessConnection _inner = new(port, "cut-once");
    private int _calls;

    public int OnCall { get; init; } = 2;

    public int Cut { get; init; }

    public bool Fired { get; private set; }

    public string Description => "cut-once";

    public Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default) => _inner.GetResponseAsync(command, cancellationToken);

    public async Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        if (++_calls != OnCall || Fired)
        {
            await _inner.DownloadAsync(lines, cancellationToken);
            return;
        }

        Fired = true;
        await _inner.DownloadAsync(lines.Take(Cut).ToList(), cancellationToken);
        throw new PmacLinkException("link reset during download");
    }

    public Task FlushAsync(CancellationToken cancellationToken = default) => _inner.FlushAsync(cancellationToken);

    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) => _inner.ControlAsync(control, cancellationToken);

    public ValueTask DisposeAsync() => ValueTask.CompletedTask;
}

/// <summary>
/// The exact mechanism of the old repeat, deterministically: a chunk download that breaks right after a non-motion
/// line (M08) which follows a move. M0 names that move; only the line probe tells that M08 arrived too.
/// </summary>
public sealed class LineProbeTests : IDisposable
{
    private readonly TestFolder _folder = new("probe");

    private (FakeRig Rig, CutOnceConnection Conn, string Folder) Setup(string? probe, Func<ChunkedProgramProbe, int> cutAt)
    {
        var folder = _folder.NewFolder("program");
        var program = FakeSplit.Write(folder, FakeSplit.Program(400, 11), 100);
        var options = new StreamingOptions { LineProbeVariable = probe, BufferWords = 8000 };
        var rig = new FakeRig(program, options, capacityWords: 8000);
        program.UseLineProbe(probe);
        var conn = new CutOnceConnection(rig.Controller) { OnCall = 2, Cut = cutAt(new ChunkedProgramProbe(program)) };
        rig.Connection = conn;
        rig.Session = rig.NewSession();
        return (rig, conn, folder);
    }

    /// <summary>Index (0-based body line) in chunk 2 of a non-motion line right after a move.</summary>
    internal sealed record ChunkedProgramProbe(ChunkedProgram Program)
    {
        public int NonMotionAfterMove()
        {
            var body = Program.Body(2);
            for (var i = 1; i < body.Count - 1; i++)
            {
                if (body[i].TrackedLine == 0 && !body[i].IsMotion && body[i - 1].TrackedLine > 0)
                {
                    return i;
                }
            }

            throw new InvalidOperationException("no non-motion line after a move in chunk 2");
        }
    }

    private static async Task RunWithRecovery(FakeRig rig)
    {
        await rig.Session.StartAsync();
        var ok = await rig.RunAsync(everyTick: async _ =>
        {
            if (rig.Session.State == SessionState.Faulted)
            {
                (await rig.Session.RecoverAsync()).Should().BeTrue();
            }
        });
        ok.Should().BeTrue(rig.Session.Status.Message);
    }

    private static (LineCounts Motion, LineCounts NonMotion) Count(FakeRig rig)
    {
        var p = rig.Program;
        var sent = Enumerable.Range(1, p.TotalChunks).SelectMany(c => p.Body(c)).Select(l => l.Text).ToList();
        return LineAccounting.Compare(sent, rig.Controller.ExecutedLines, t => p.Classify(t) is { } l && (l.IsMotion || l.TrackedLine > 0));
    }

    [Fact]
    public async Task A_download_broken_right_after_M08_resumes_after_it_with_the_probe()
    {
        // Framing "CLOSE", "OPEN ROT" come first in the file: cut after the M08 line of the body.
        var (rig, conn, folder) = Setup("P501", p => 2 + p.NonMotionAfterMove() + 1);
        await RunWithRecovery(rig);
        conn.Fired.Should().BeTrue();
        var (motion, nonMotion) = Count(rig);
        motion.Exact.Should().BeTrue(motion.ToString());
        nonMotion.Exact.Should().BeTrue($"M08 ran once: {nonMotion}");
        Directory.Delete(folder, true);
    }

    [Fact]
    public async Task Without_the_probe_the_same_break_runs_M08_twice()
    {
        var (rig, conn, folder) = Setup(null, p => 2 + p.NonMotionAfterMove() + 1);
        await RunWithRecovery(rig);
        conn.Fired.Should().BeTrue();
        var (motion, nonMotion) = Count(rig);
        motion.Exact.Should().BeTrue();
        nonMotion.Repeated.Should().Be(1, "the old mechanism: resume after M0's move re-sends the M08 that had arrived");
        Directory.Delete(folder, true);
    }

    [Fact]
    public async Task A_probe_value_written_by_someone_else_is_not_trusted()
    {
        // The break leaves M08 undelivered (cut just before it); meanwhile something writes P501 far ahead.
        var (rig, conn, folder) = Setup("P501", p => 2 + p.NonMotionAfterMove());
        await rig.Session.StartAsync();
        var bogus = 0;
        bool recovered = false, sendingAgain = false;
        var ok = await rig.RunAsync(everyTick: async _ =>
        {
            if (rig.Session.State == SessionState.Faulted)
            {
                (await rig.Session.RecoverAsync()).Should().BeTrue();
                recovered = true;
            }
            else if (recovered && !sendingAgain)
            {
                // While the session waits for the drain, keep a foreign value in the probe variable.
                if (rig.Session.Status.Message.Contains("waiting for the buffer to drain", StringComparison.Ordinal))
                {
                    rig.Controller.P[501] = ChunkedProgram.ProbeValue(new StreamPosition(4, 3));
                    bogus++;
                }
                else
                {
                    sendingAgain = true;
                }
            }
        });
        ok.Should().BeTrue(rig.Session.Status.Message);
        bogus.Should().BeGreaterThan(0);
        conn.Fired.Should().BeTrue();
        var (motion, nonMotion) = Count(rig);
        motion.Exact.Should().BeTrue($"nothing skipped on a foreign probe value: {motion}");
        nonMotion.Exact.Should().BeTrue(nonMotion.ToString());
        Directory.Delete(folder, true);
    }

    [Fact]
    public void Probe_annotation_keeps_labels_first_and_the_download_copy_line_for_line()
    {
        using var temp = new TestFolder("probe-copy");
        var folder = temp.Path;
        var program = FakeSplit.Write(folder, FakeSplit.Program(300, 5), 100);
        program.UseLineProbe("p501");
        program.LineProbeVariable.Should().Be("P501");

        var body = program.Body(1);
        body.Where(b => b.TrackedLine == 0 && !b.IsMotion).Should().NotBeEmpty()
            .And.OnlyContain(b => b.Text.StartsWith("P501=", StringComparison.Ordinal));
        body.Where(b => b.TrackedLine > 0).Should().OnlyContain(b => !b.Text.Contains("P501", StringComparison.Ordinal), "exact placement: moves need no probe");
        var i = body.ToList().FindIndex(b => b.TrackedLine == 0 && !b.IsMotion);
        program.PositionAfterProbe(ChunkedProgram.ProbeValue(new StreamPosition(1, i))).Should().Be(program.Normalize(new StreamPosition(1, i + 1)));
        program.PositionAfterProbe(0).Should().BeNull();
        program.PositionAfterProbe(ChunkedProgram.ProbeValue(new StreamPosition(99, 0))).Should().BeNull();

        var copy = program.SendPath(1, out var temporary);
        temporary.Should().BeTrue();
        var original = File.ReadAllLines(program.ChunkPath(1));
        var sent = File.ReadAllLines(copy);
        sent.Should().HaveCount(original.Length, "line for line, so a refused line keeps its file line");
        foreach (var b in body)
        {
            sent[b.FileLine - 1].Should().Be(b.Text);
        }

        Directory.Delete(Path.GetDirectoryName(copy)!, true);
        Assert.Throws<ArgumentException>(() => program.UseLineProbe("M501"));
        program.UseLineProbe(null);
        program.Body(1).Should().OnlyContain(b => !b.Text.Contains("P501", StringComparison.Ordinal));
        program.SendPath(1, out var again).Should().Be(program.ChunkPath(1));
        again.Should().BeFalse();
        Directory.Delete(folder, true);

        // An N label must lead its line: the probe goes right after it.
        using var temp2 = new TestFolder("probe-n");
        var labelled = FakeSplit.Write(temp2.Path, ["G01 X1 Y1", "N120 M08", "G01 X2 Y2"], 10);
        labelled.UseLineProbe("P501");
        labelled.Body(1)[1].Text.Should().Be($"N120 P501={ChunkedProgram.ProbeValue(new StreamPosition(1, 1))} M08");
        Directory.Delete(labelled.Folder, true);
    }

    public void Dispose() => _folder.Dispose();
}
