using System.Security.Cryptography;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Testing;

/// <summary>A TimeProvider the test moves by hand, so sessions see the fake controller's virtual time.</summary>
public sealed class ManualTime : TimeProvider
{
    private long _ticks;

    public override long TimestampFrequency => TimeSpan.TicksPerSecond;

    public override long GetTimestamp() => _ticks;

    public override DateTimeOffset GetUtcNow() => new DateTimeOffset(2026, 1, 1, 0, 0, 0, TimeSpan.Zero).AddTicks(_ticks);

    public void Advance(double seconds) => _ticks += (long)(seconds * TimeSpan.TicksPerSecond);
}

/// <summary>
/// Writes a split program the way the splitter's contract says (chunk files <c>name_0001.pmc</c>: CLOSE, OPEN ROT,
/// lines with M0==line before each motion block's words and F(P500), CLOSE; manifest.json), from synthetic G-code.
/// Stands in for the real splitter in unit tests so they stay independent of its details.
/// </summary>
public static class FakeSplit
{
    public static string[] Program(int lines, int seed)
    {
        var r = new Random(seed);
        var src = new string[lines];
        for (var i = 0; i < lines; i++)
        {
            src[i] = r.Next(10) switch
            {
                0 => "(comment)",
                1 => "M08",
                2 => string.Empty,
                _ => $"G01 X{r.Next(100)}.{r.Next(10)} Y{r.Next(100)} Z-{r.Next(3)}",
            };
        }

        return src;
    }

    public static ChunkedProgram Write(string folder, string[] source, int linesPerChunk, TrackingPlacement placement = TrackingPlacement.Exact)
    {
        Directory.CreateDirectory(folder);
        var chunks = new List<ChunkInfo>();
        int total = 0, totalMotion = 0;
        for (var start = 0; start < source.Length; start += linesPerChunk)
        {
            var index = chunks.Count + 1;
            var name = $"prog_{index:0000}.pmc";
            var sb = new StringBuilder("CLOSE\nOPEN ROT\n");
            int blocks = 0, motion = 0, words = 0;
            var end = Math.Min(source.Length, start + linesPerChunk);
            for (var i = start; i < end; i++)
            {
                var t = source[i];
                if (t.Length == 0 || t.StartsWith('('))
                {
                    continue;
                }

                var n = i + 1;
                string line;
                if (t.Contains('X'))
                {
                    line = placement == TrackingPlacement.Exact ? $"M0=={n} {t} F(P500)" : $"{t} F(P500) M0=={n}";
                    motion++;
                }
                else
                {
                    line = t;
                }

                blocks++;
                words += FakeRotaryController.WordsOf(line);
                sb.Append(line).Append('\n');
            }

            sb.Append("CLOSE\n");
            var path = Path.Combine(folder, name);
            File.WriteAllText(path, sb.ToString());
            var bytes = File.ReadAllBytes(path);
            chunks.Add(new ChunkInfo(index, name, start + 1, end, blocks, motion, bytes.Length, words, Convert.ToHexString(SHA256.HashData(bytes))));
            total += blocks;
            totalMotion += motion;
        }

        var manifest = new ChunkManifest("prog.nc", 0, "00", total, totalMotion, "M0", placement, FeedMode.Paper, "P500", chunks);
        manifest.Save(Path.Combine(folder, ChunkManifest.FileName));
        return ChunkedProgram.Open(folder);
    }
}

/// <summary>
/// The rig's streaming layer in its fake-controller mode: a <see cref="FakeRotaryController"/> (buffer size and move
/// time the test sets, protocol violations recorded), a session on it and a loop that ticks and advances virtual time
/// together. <see cref="SimRig"/> is the same layer on the real simulator and the real splitter.
/// </summary>
public sealed class FakeRig
{
    public FakeRig(ChunkedProgram program, StreamingOptions options, IPmacConnection? connection = null, double moveSeconds = 0.01, int capacityWords = 4000)
    {
        Program = program;
        Options = options;
        Controller = new FakeRotaryController { MoveSeconds = moveSeconds, CapacityWords = capacityWords };
        Connection = connection ?? new InProcessConnection(Controller);
        Session = NewSession();
    }

    public ChunkedProgram Program { get; }

    public StreamingOptions Options { get; }

    public FakeRotaryController Controller { get; }

    public IPmacConnection Connection { get; set; }

    public ManualTime Time { get; } = new();

    public MemorySink Sink { get; } = new();

    public StreamingSession Session { get; set; }

    public StreamingSession NewSession() => new(Connection, Program, Options, Sink, time: Time);

    public void Advance(double seconds)
    {
        Controller.Advance(seconds);
        Time.Advance(seconds);
    }

    /// <summary>Ticks until the session completes and the last move ends (or the tick budget runs out).</summary>
    public async Task<bool> RunAsync(int maxTicks = 200_000, Func<int, Task>? everyTick = null)
    {
        var dt = Options.TickPeriod.TotalSeconds;
        for (var i = 0; i < maxTicks; i++)
        {
            await Session.TickAsync();
            if (everyTick is not null)
            {
                await everyTick(i);
            }

            if (Session.State == SessionState.Completed && !Controller.InMove)
            {
                return true;
            }

            Advance(dt);
        }

        return false;
    }

    /// <summary>The source line of each block executed, in execution order (what the demo counts).</summary>
    public List<int> ExecutedLines() => MoveLines.Blocks(Controller.Moves.Select(m => (m.SourceLine, m.BlockStart)), Program);
}
