using System.Buffers.Binary;
using System.Text;
using PmacStream.Pmac;
using Serilog;

namespace PmacStream.Sim.Servers;

/// <summary>Why a <see cref="VrPmacSession"/> ended.</summary>
public enum SessionEnd
{
    /// <summary>The client closed the connection between packets.</summary>
    ClientClosed,

    /// <summary>A malformed or truncated packet (the documented protocol error): the connection is closed.</summary>
    Malformed,

    /// <summary>No packet for <see cref="PmacTcpServerOptions.IdleTimeout"/>.</summary>
    Idle,

    /// <summary>The server stopped, or closed the connection (to serve another client, or on request).</summary>
    Stopped,
}

/// <summary>Counters a server's sessions share (read with <see cref="Interlocked"/>).</summary>
internal sealed class VrPmacCounters
{
    public long Packets;
    public long Malformed;
    public long IdleClosed;
    public long DroppedReplies;
}

/// <summary>
/// One client's side of the VR_PMAC packet protocol over a byte stream (a TCP connection, or a fuzzer's bytes): reads
/// packets, runs them on its engine port and writes the replies. The parser of untrusted bytes: a malformed or
/// truncated packet ends the session with <see cref="SessionEnd.Malformed"/>, silence with <see cref="SessionEnd.Idle"/>;
/// nothing a client sends makes it throw (the stream's own I/O errors excepted).
/// </summary>
internal sealed class VrPmacSession
{
    private static readonly ILogger Log = Serilog.Log.ForContext<VrPmacSession>();
    private readonly Stream _stream;
    private readonly IPmacPortEndpoint _port;
    private readonly object _engineLock;
    private readonly PmacTcpServerOptions _options;
    private readonly VrPmacCounters _counters;
    private readonly int _id;
    private static readonly ReadOnlyMemory<byte> NoReply = new byte[] { 0 };
    private readonly byte[] _header = new byte[VrPmac.HeaderSize];
    private readonly byte[] _data = new byte[VrPmac.MaxData];
    private readonly byte[] _out = new byte[VrPmac.MaxReply + 8];
    private readonly PendingReplies _pending;
    private readonly ReadDeadline _deadline = new();
    private long _lastActivity = Environment.TickCount64;

    public VrPmacSession(Stream stream, IPmacPortEndpoint port, object engineLock, PmacTcpServerOptions options, VrPmacCounters counters, int id)
    {
        _stream = stream;
        _port = port;
        _engineLock = engineLock;
        _options = options;
        _counters = counters;
        _id = id;
        _pending = new PendingReplies(options.MaxPendingReplyBytes);
    }

    /// <summary>When the last packet started arriving (<see cref="Environment.TickCount64"/>): how idle the client is.</summary>
    public long LastActivity => Interlocked.Read(ref _lastActivity);

    /// <summary>Bytes of replies waiting to be fetched.</summary>
    public int PendingBytes => _pending.Count;

    /// <summary>Serves packets until the client leaves, errs, falls silent or <paramref name="stop"/> is cancelled.</summary>
    public async Task<SessionEnd> RunAsync(CancellationToken stop)
    {
        try
        {
            return await ServeAsync(stop).ConfigureAwait(false);
        }
        finally
        {
            _deadline.Dispose();
        }
    }

    private async Task<SessionEnd> ServeAsync(CancellationToken stop)
    {
        while (true)
        {
            var first = await ReadPacketPartAsync(_header, VrPmac.HeaderSize, stop, first: true).ConfigureAwait(false);
            if (first != null)
            {
                return first.Value;
            }

            var type = _header[0];
            var request = _header[1];
            var wValue = BinaryPrimitives.ReadUInt16BigEndian(_header.AsSpan(2));
            var wLength = BinaryPrimitives.ReadUInt16BigEndian(_header.AsSpan(6));
            if (type != VrPmac.Download && type != VrPmac.Upload)
            {
                return Malformed($"request type 0x{type:X2}");
            }

            var length = 0;
            if (type == VrPmac.Download)
            {
                if (wLength > VrPmac.MaxData)
                {
                    return Malformed($"wLength {wLength} > {VrPmac.MaxData}");
                }

                length = wLength;
                if (length > 0 && await ReadPacketPartAsync(_data, length, stop, first: false).ConfigureAwait(false) is { } end)
                {
                    return end;
                }
            }

            if (!await HandleAsync(type, request, wValue, length, stop).ConfigureAwait(false))
            {
                return SessionEnd.Malformed;
            }

            Interlocked.Increment(ref _counters.Packets);
        }
    }

    private async Task<bool> HandleAsync(byte type, byte request, ushort wValue, int length, CancellationToken stop)
    {
        switch (request)
        {
            case VrPmac.GetResponse when type == VrPmac.Download:
                {
                    var command = Command(_data.AsSpan(0, length));
                    await DelayAsync(stop).ConfigureAwait(false);
                    _pending.Replace(Execute(command));
                    await SendPendingReplyAsync(stop).ConfigureAwait(false);
                    return true;
                }

            case VrPmac.SendLine when type == VrPmac.Download:
                {
                    var dropped = _pending.Add(Execute(Command(_data.AsSpan(0, length))));
                    if (dropped > 0)
                    {
                        Interlocked.Add(ref _counters.DroppedReplies, dropped);
                        Log.Debug("tcp {Id}: reply buffer full ({Capacity} bytes): {Dropped} oldest unfetched replies dropped", _id, _pending.Capacity, dropped);
                    }

                    await SendAsync(new byte[] { request }, stop).ConfigureAwait(false);
                    return true;
                }

            case VrPmac.GetLine:
            case VrPmac.GetBuffer:
                await SendPendingReplyAsync(stop).ConfigureAwait(false);
                return true;

            case VrPmac.ReadReady:
                await SendAsync(new byte[] { _pending.Count > 0 ? (byte)1 : (byte)0, 0 }, stop).ConfigureAwait(false);
                return true;

            case VrPmac.Flush:
                lock (_engineLock)
                {
                    _port.Flush();
                }

                _pending.Clear();
                Log.Debug("tcp {Id} > <FLUSH>", _id);
                await SendAsync(new byte[] { request }, stop).ConfigureAwait(false);
                return true;

            case VrPmac.CtrlResponse:
                {
                    // Drivers disagree on wValue's byte order: take the character from whichever byte holds it.
                    var c = (char)((wValue >> 8) != 0 ? wValue >> 8 : wValue & 0xFF);
                    byte[] reply;
                    lock (_engineLock)
                    {
                        reply = c == 0 ? [] : _port.Control(c);
                    }

                    Log.Debug("tcp {Id} > <CTRL-{Char}> < {Reply}", _id, (char)(c + 64), ReplyParser.Visible(reply));
                    var n = Math.Min(reply.Length, VrPmac.MaxReply);
                    await SendAsync(n == 0 ? new byte[] { 0 } : reply.AsMemory(0, n), stop).ConfigureAwait(false);
                    return true;
                }

            case VrPmac.WriteBuffer when type == VrPmac.Download:
                await DelayAsync(stop).ConfigureAwait(false);
                WriteBuffer(length);
                await SendAsync(_out.AsMemory(0, 4), stop).ConfigureAwait(false);
                return true;

            default:
                Malformed($"unsupported request 0x{type:X2}/0x{request:X2}");
                return false;
        }
    }

    private void WriteBuffer(int length)
    {
        if (length > VrPmac.MaxWriteBuffer)
        {
            Log.Warning("tcp {Id}: WRITEBUFFER of {Length} bytes refused (at most {Max})", _id, length, VrPmac.MaxWriteBuffer);
            VrPmac.WriteBufferStatus(_out, PmacErrors.UnknownCommand, 0);
            return;
        }

        var data = _data.AsSpan(0, length);
        var line = 0;
        while (!data.IsEmpty)
        {
            var nul = data.IndexOf((byte)0);
            var text = nul >= 0 ? data[..nul] : data;
            data = nul >= 0 ? data[(nul + 1)..] : [];
            var reply = Execute(Command(text), quiet: true);
            if (Array.IndexOf(reply, ReplyParser.Bel) >= 0)
            {
                var number = ErrorNumber(reply);
                Log.Debug("tcp {Id} WRITEBUFFER line {Line} refused: ERR{Number:000}", _id, line, number);
                VrPmac.WriteBufferStatus(_out, number, line);
                return;
            }

            line++;
        }

        Log.Debug("tcp {Id} WRITEBUFFER {Lines} lines accepted", _id, line);
        VrPmac.WriteBufferStatus(_out, 0, 0);
    }

    private byte[] Execute(string command, bool quiet = false)
    {
        byte[] reply;
        lock (_engineLock)
        {
            reply = _port.Execute(command);
        }

        if (!quiet && Log.IsEnabled(Serilog.Events.LogEventLevel.Debug))
        {
            Log.Debug("tcp {Id} > {Command} < {Reply}", _id, command, ReplyParser.Visible(reply));
        }

        return reply;
    }

    /// <summary>Sends the first reply waiting by the controller's termination rules, at most 1400 bytes; one NUL when none.</summary>
    private Task SendPendingReplyAsync(CancellationToken stop)
    {
        if (_pending.Count == 0)
        {
            return SendAsync(NoReply, stop);
        }

        var n = _pending.Take(_out.AsSpan(0, VrPmac.MaxReply));
        return SendAsync(_out.AsMemory(0, n), stop);
    }

    private async Task SendAsync(ReadOnlyMemory<byte> bytes, CancellationToken stop) =>
        await _stream.WriteAsync(bytes, stop).ConfigureAwait(false);

    private Task DelayAsync(CancellationToken stop) =>
        _options.ResponseDelay > TimeSpan.Zero ? Task.Delay(_options.ResponseDelay, stop) : Task.CompletedTask;

    /// <summary>
    /// Reads <paramref name="count"/> bytes. The first byte of a packet may take up to the idle timeout; once a packet
    /// has started, the rest must come within the packet timeout. Null when all arrived, else why the session ends.
    /// </summary>
    private async Task<SessionEnd?> ReadPacketPartAsync(byte[] buffer, int count, CancellationToken stop, bool first)
    {
        var n = 0;
        if (first)
        {
            try
            {
                n = await _stream.ReadAsync(buffer.AsMemory(0, count), _deadline.Arm(stop, _options.IdleTimeout)).ConfigureAwait(false);
            }
            catch (OperationCanceledException) when (!stop.IsCancellationRequested)
            {
                Interlocked.Increment(ref _counters.IdleClosed);
                Log.Information("tcp client {Id}: no packet for {Seconds:0} s; connection closed", _id, _options.IdleTimeout.TotalSeconds);
                return SessionEnd.Idle;
            }

            if (n == 0)
            {
                return SessionEnd.ClientClosed;
            }

            Interlocked.Exchange(ref _lastActivity, Environment.TickCount64);
        }

        // Usually the whole packet came with its first read: no deadline to arm then.
        var rest = n < count ? _deadline.Arm(stop, _options.PacketTimeout) : stop;
        while (n < count)
        {
            int got;
            try
            {
                got = await _stream.ReadAsync(buffer.AsMemory(n, count - n), rest).ConfigureAwait(false);
            }
            catch (OperationCanceledException) when (!stop.IsCancellationRequested)
            {
                got = 0;
            }

            if (got == 0)
            {
                return Malformed("packet truncated");
            }

            n += got;
        }

        _deadline.Disarm();
        return null;
    }

    private SessionEnd Malformed(string why)
    {
        Interlocked.Increment(ref _counters.Malformed);
        Log.Warning("tcp client {Id}: {Why}; connection closed", _id, why);
        return SessionEnd.Malformed;
    }

    private static string Command(ReadOnlySpan<byte> data)
    {
        // Hosts may or may not end the command with CR or NUL; the controller ignores them.
        while (!data.IsEmpty && (data[^1] == ReplyParser.Cr || data[^1] == 0 || data[^1] == 0x0A))
        {
            data = data[..^1];
        }

        return Encoding.Latin1.GetString(data);
    }

    private static int ErrorNumber(byte[] reply)
    {
        var text = Encoding.ASCII.GetString(reply);
        var i = text.IndexOf("ERR", StringComparison.Ordinal);
        if (i >= 0 && i + 6 <= text.Length && int.TryParse(text.AsSpan(i + 3, 3), out var n))
        {
            return n;
        }

        return PmacErrors.UnknownCommand;
    }
}
