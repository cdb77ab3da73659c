using System.Text.RegularExpressions;
using PmacStream.Pmac;
using PmacStream.Streaming;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>Records every line a port receives, so tests see the chunks exactly as the controller got them.</summary>
internal sealed class RecordingPort(IPmacPortEndpoint inner) : IPmacPortEndpoint
{
    public List<string> Lines { get; } = new();

    public byte[] Execute(string commandLine)
    {
        Lines.Add(commandLine);
        return inner.Execute(commandLine);
    }

    public void Flush() => inner.Flush();

    public byte[] Control(char control) => inner.Control(control);
}

public class ChunkTranscriptTests
{
    [Fact]
    public async Task Chunks_reach_the_controller_framed_annotated_and_in_source_order()
    {
        using var rig = new SimRig(RepoRoot.DemoProgram, 1000, new StreamingOptions { BufferWords = 20_000 });
        var rec = new RecordingPort(rig.Port);
        rig.Connection = new InProcessConnection(rec, "recorded");
        rig.Session = new StreamingSession(rig.Connection, rig.Program, rig.Options, rig.Sink, time: rig.Time);
        await rig.Session.StartAsync();
        (await rig.RunAsync(2.0)).Should().BeTrue();

        // Cut the transcript into what was sent between OPEN ROT and CLOSE.
        var chunks = new List<List<string>>();
        List<string>? current = null;
        var b0 = -1;
        for (var i = 0; i < rec.Lines.Count; i++)
        {
            var l = rec.Lines[i];
            if (Regex.IsMatch(l, @"^&1\s*B0$"))
            {
                b0 = i;
            }

            if (l == "OPEN ROT" && i + 1 < rec.Lines.Count && rec.Lines[i + 1] == "CLEAR")
            {
                // The start clears the buffer (leftovers of an earlier job would run first): not a chunk.
                b0.Should().BeGreaterThanOrEqualTo(0, "&1 B0 is sent before the first OPEN ROT");
                rec.Lines[i + 2].Should().Be("CLOSE");
                i += 2;
                continue;
            }

            if (l == "OPEN ROT")
            {
                b0.Should().BeGreaterThanOrEqualTo(0, "&1 B0 is sent before the first OPEN ROT");
                rec.Lines[i - 1].Should().Be("CLOSE", "each chunk begins CLOSE, OPEN ROT");
                current = new List<string>();
                chunks.Add(current);
            }
            else if (l == "CLOSE" && current is not null)
            {
                current = null;
            }
            else if (current is not null)
            {
                current.Add(l);
                l.Should().NotMatchRegex(@"^(M0|PR|P500|&1.*)$", "no online command while the buffer is open");
            }
        }

        chunks.Should().HaveCount(rig.Program.TotalChunks);
        var previousLast = 0;
        for (var k = 0; k < chunks.Count; k++)
        {
            var info = rig.Program.Chunk(k + 1);
            chunks[k].Should().Equal(rig.Program.Body(k + 1).Select(b => b.Text), $"chunk {k + 1} arrives whole and unchanged");
            var tracked = chunks[k].Select(l => Regex.Match(l, @"M0==(\d+)")).Where(m => m.Success).Select(m => int.Parse(m.Groups[1].Value)).ToList();
            tracked.Should().HaveCount(info.MotionBlockCount);
            tracked.Should().BeInAscendingOrder().And.OnlyHaveUniqueItems();
            tracked.First().Should().BeGreaterThan(previousLast, "chunks follow each other in source order");
            tracked.Should().OnlyContain(t => t >= info.FirstSourceLine && t <= info.LastSourceLine);
            previousLast = tracked.Last();
            chunks[k].Where(l => l.Contains("M0==", StringComparison.Ordinal)).Should().OnlyContain(l => l.Contains("F(P500)", StringComparison.Ordinal));
        }

        rig.ExecutedLines().Should().Equal(rig.Program.TrackedLines());
    }
}
