using System.Collections.Concurrent;
using System.Net;
using System.Text;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Testing;

/// <summary>
/// A scripted controller behind the real servers, for server and transport tests: P variables, VER, LONG n (an n-character
/// reply), SLEEP n (answers after n ms: a slow controller), anything containing BAD refused with ERR003, every other
/// line recorded as executed, in order, across ports (what the controller really ran: server-side evidence).
/// </summary>
public sealed class ScriptedController
{
    private readonly Func<string, string>? _reply;

    /// <summary>The controller of the script above.</summary>
    public ScriptedController()
    {
    }

    /// <summary>
    /// A controller that answers every line with <paramref name="reply"/>'s text instead (values separated by CR;
    /// <c>ERRnnn</c> an error reply), recording each line as sent, for the streaming layer's query and channel tests.
    /// </summary>
    public ScriptedController(Func<string, string> reply) => _reply = reply;

    /// <summary>Lines run, in order, as received (trimmed).</summary>
    public ConcurrentQueue<string> Executed { get; } = new();

    /// <summary>P variables written so far.</summary>
    public ConcurrentDictionary<int, string> P { get; } = new();

    /// <summary>Ctrl-X flushes received (all ports).</summary>
    public int Flushes;

    /// <summary>A new communication port on this controller (one per server client or serial line).</summary>
    public IPmacPortEndpoint OpenPort() => new Port(this);

    /// <summary>A started TCP server on a free loopback port, a new port per client.</summary>
    public PmacTcpServer StartTcp(TimeSpan? responseDelay = null)
    {
        var server = new PmacTcpServer(OpenPort, new PmacTcpServerOptions { EndPoint = new IPEndPoint(IPAddress.Loopback, 0), ResponseDelay = responseDelay ?? TimeSpan.Zero });
        server.Start();
        return server;
    }

    private sealed class Port(ScriptedController c) : IPmacPortEndpoint
    {
        public byte[] Execute(string commandLine)
        {
            if (c._reply is { } reply)
            {
                c.Executed.Enqueue(commandLine);
                var text = reply(commandLine);
                return text.StartsWith("ERR", StringComparison.Ordinal)
                    ? Encoding.ASCII.GetBytes("\a" + text + "\r")
                    : Encoding.ASCII.GetBytes(text.Length == 0 ? "\x06" : text + "\r\x06");
            }

            var cmd = commandLine.Trim();
            var upper = cmd.ToUpperInvariant();
            if (upper.Contains("BAD", StringComparison.Ordinal))
            {
                return Encoding.ASCII.GetBytes("\aERR003\r");
            }

            if (upper.Length == 0)
            {
                return [ReplyParser.Ack];
            }

            if (upper == "VER")
            {
                return Encoding.ASCII.GetBytes("1.947\r\x06");
            }

            if (upper.StartsWith("SLEEP ", StringComparison.Ordinal))
            {
                Thread.Sleep(int.Parse(upper.AsSpan(6)));
                return [ReplyParser.Ack];
            }

            if (upper.StartsWith("LONG ", StringComparison.Ordinal))
            {
                var n = int.Parse(upper.AsSpan(5));
                var sb = new StringBuilder(n + 2);
                for (var i = 0; i < n; i++)
                {
                    sb.Append((char)('A' + (i % 26)));
                }

                return Encoding.ASCII.GetBytes(sb.Append("\r\x06").ToString());
            }

            if (upper.StartsWith('P') && int.TryParse(upper.AsSpan(1), out var read))
            {
                return Encoding.ASCII.GetBytes((c.P.TryGetValue(read, out var v) ? v : "0") + "\r\x06");
            }

            var eq = upper.IndexOf('=');
            if (upper.StartsWith('P') && eq > 1 && int.TryParse(upper.AsSpan(1, eq - 1), out var write))
            {
                c.P[write] = upper[(eq + 1)..];
            }

            c.Executed.Enqueue(cmd);
            return [ReplyParser.Ack];
        }

        public void Flush() => Interlocked.Increment(ref c.Flushes);

        public byte[] Control(char control) => control == '\x02' ? Encoding.ASCII.GetBytes("812000804001\r") : [];
    }
}
