using System.Diagnostics;
using System.Text;
using Serilog;

namespace PmacStream.Pmac;

/// <summary>
/// A connection straight into a controller engine's port (the simulator), for fast tests and the demo. It parses
/// the same reply framing as the serial transport, so what is tested here is the protocol, not a shortcut.
/// </summary>
public sealed class InProcessConnection : IPmacConnection
{
    private static readonly ILogger Log = Serilog.Log.ForContext<InProcessConnection>();
    private readonly IPmacPortEndpoint _port;
    private readonly SemaphoreSlim _gate = new(1, 1);

    /// <summary>Wraps an engine port.</summary>
    public InProcessConnection(IPmacPortEndpoint port, string description = "in-process")
    {
        _port = port;
        Description = description;
    }

    /// <inheritdoc />
    public string Description { get; }

    /// <inheritdoc />
    public async Task<string> GetResponseAsync(string command, CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            var sw = Stopwatch.StartNew();
            var raw = _port.Execute(command);
            if (Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
            {
                Log.Debug("{Device} > {Command} < {Reply} ({Ms:0.000} ms)", Description, command, Visible(raw), sw.Elapsed.TotalMilliseconds);
            }
            return ReplyParser.Parse(raw, command);
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public async Task DownloadAsync(IReadOnlyList<string> lines, CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            for (var i = 0; i < lines.Count; i++)
            {
                cancellationToken.ThrowIfCancellationRequested();
                var raw = _port.Execute(lines[i]);
                try
                {
                    ReplyParser.Parse(raw, lines[i]);
                }
                catch (PmacErrorException e)
                {
                    Log.Debug("{Device} download refused line {Index}: {Line} -> ERR{Number:000}", Description, i, lines[i], e.Number);
                    throw new PmacErrorException(e.Number, lines[i], i);
                }
            }

            Log.Debug("{Device} downloaded {Count} lines", Description, lines.Count);
        }
        finally
        {
            _gate.Release();
        }
    }

    /// <inheritdoc />
    public Task FlushAsync(CancellationToken cancellationToken = default)
    {
        _port.Flush();
        return Task.CompletedTask;
    }

    /// <inheritdoc />
    public Task<string> ControlAsync(char control, CancellationToken cancellationToken = default) =>
        Task.FromResult(Encoding.ASCII.GetString(_port.Control(control)));

    /// <inheritdoc />
    public ValueTask DisposeAsync() => ValueTask.CompletedTask;

    internal static string Visible(ReadOnlySpan<byte> raw) => ReplyParser.Visible(raw);
}
