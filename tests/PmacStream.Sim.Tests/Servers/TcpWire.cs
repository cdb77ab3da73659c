using System.Buffers.Binary;
using System.Net;
using System.Net.Sockets;
using System.Text;
using PmacStream.Pmac;

namespace PmacStream.Sim.Tests.Servers;

/// <summary>A raw VR_PMAC client for transcript tests: bytes in, bytes out, nothing interpreted.</summary>
internal sealed class TcpWire : IDisposable
{
    private readonly Socket _socket;

    public TcpWire(int port)
    {
        _socket = new Socket(SocketType.Stream, ProtocolType.Tcp) { NoDelay = true, ReceiveTimeout = 5000 };
        _socket.Connect(new IPEndPoint(IPAddress.Loopback, port));
    }

    public Socket Socket => _socket;

    public static byte[] Packet(byte type, byte request, ushort wValue, ushort wLength, ReadOnlySpan<byte> data)
    {
        var p = new byte[8 + data.Length];
        p[0] = type;
        p[1] = request;
        BinaryPrimitives.WriteUInt16BigEndian(p.AsSpan(2), wValue);
        BinaryPrimitives.WriteUInt16BigEndian(p.AsSpan(6), wLength);
        data.CopyTo(p.AsSpan(8));
        return p;
    }

    public void Send(byte[] bytes) => _socket.Send(bytes);

    /// <summary>Sends a GETRESPONSE and returns exactly what comes back in one reply packet.</summary>
    public byte[] GetResponse(string command)
    {
        var data = Encoding.ASCII.GetBytes(command);
        Send(Packet(VrPmac.Download, VrPmac.GetResponse, 0, (ushort)data.Length, data));
        return ReceiveReply();
    }

    public byte[] ReceiveReply()
    {
        var buffer = new byte[2000];
        var n = 0;
        while (n < VrPmac.MaxReply)
        {
            var got = _socket.Receive(buffer, n, VrPmac.MaxReply - n, SocketFlags.None);
            if (got == 0)
            {
                break;
            }

            n += got;
            if (VrPmac.ReplyLength(buffer.AsSpan(0, n)) >= 0 || (n == 1 && buffer[0] == 0))
            {
                break;
            }
        }

        return buffer[..n];
    }

    public byte[] ReceiveExactly(int count)
    {
        var buffer = new byte[count];
        var n = 0;
        while (n < count)
        {
            var got = _socket.Receive(buffer, n, count - n, SocketFlags.None);
            if (got == 0)
            {
                throw new IOException($"closed after {n} of {count} bytes");
            }

            n += got;
        }

        return buffer;
    }

    /// <summary>True when the server closed the connection (a receive returns 0 or fails) within the timeout.</summary>
    public bool IsClosedByServer()
    {
        try
        {
            return _socket.Receive(new byte[64]) == 0;
        }
        catch (SocketException e) when (e.SocketErrorCode == SocketError.ConnectionReset)
        {
            return true;
        }
    }

    public void Dispose() => _socket.Dispose();
}
