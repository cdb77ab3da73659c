using System.Collections.Concurrent;
using System.Text;
using PmacStream.Pmac;

namespace PmacStream.Sim.Tests.Servers;

/// <summary>
/// A tiny stand-in engine port for server tests: P variables, VER, LONG n (n-character reply), anything containing
/// BAD refused with ERR003, every other line recorded as executed. Shared state across ports like one controller.
/// </summary>
internal sealed class FakeController
{
    public ConcurrentQueue<string> Executed { get; } = new();

    public ConcurrentDictionary<int, string> P { get; } = new();

    public int Flushes;

    public IPmacPortEndpoint OpenPort() => new FakePort(this);

    private sealed class FakePort(FakeController c) : IPmacPortEndpoint
    {
        public byte[] Execute(string commandLine)
        {
            var cmd = commandLine.Trim().ToUpperInvariant();
            if (cmd.Contains("BAD", StringComparison.Ordinal))
            {
                return Encoding.ASCII.GetBytes("\aERR003\r");
            }

            if (cmd.Length == 0)
            {
                return [ReplyParser.Ack];
            }

            if (cmd == "VER")
            {
                return Encoding.ASCII.GetBytes("1.947\r\x06");
            }

            if (cmd.StartsWith("LONG ", StringComparison.Ordinal))
            {
                var n = int.Parse(cmd.AsSpan(5));
                var sb = new StringBuilder(n + 2);
                for (var i = 0; i < n; i++)
                {
                    sb.Append((char)('A' + (i % 26)));
                }

                return Encoding.ASCII.GetBytes(sb.Append('\r').Append('\x06').ToString());
            }

            if (cmd.StartsWith('P') && int.TryParse(cmd.AsSpan(1), out var read))
            {
                return Encoding.ASCII.GetBytes((c.P.TryGetValue(read, out var v) ? v : "0") + "\r\x06");
            }

            var eq = cmd.IndexOf('=');
            if (cmd.StartsWith('P') && eq > 1 && int.TryParse(cmd.AsSpan(1, eq - 1), out var write))
            {
                c.P[write] = cmd[(eq + 1)..];
            }

            c.Executed.Enqueue(commandLine);
            return [ReplyParser.Ack];
        }

        public void Flush() => Interlocked.Increment(ref c.Flushes);

        public byte[] Control(char control) => control == '\x02' ? Encoding.ASCII.GetBytes("812000804001\r") : [];
    }
}
