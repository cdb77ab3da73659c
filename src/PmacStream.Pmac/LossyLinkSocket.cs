using System.Net.Sockets;
using Serilog;

namespace PmacStream.Pmac;

/// <summary>
/// Shortens the stalls a lost packet causes on the host's side of a controller link (issue 28). The VR_PMAC protocol
/// has one request in flight and waits for its reply, so a lost request never gets the duplicate ACKs of fast
/// retransmit: it waits for the retransmission timeout, at least 200 ms on Linux (<c>net.ipv4.tcp_rto_min_us</c>),
/// doubled on each further loss, while a plant Ethernet round trip is about a millisecond. On Linux 6.15 and later
/// the socket's own floor is lowered (<c>TCP_RTO_MIN_US</c>; the timeout stays the kernel's smoothed round trip plus
/// four deviations above it), and thin-stream linear timeouts keep a second loss from doubling the wait. Other
/// systems, and older kernels that refuse the options, keep their defaults. The controller's side (lost replies) is
/// its own TCP stack's and cannot be changed from here; the streaming lead covers those stalls.
/// </summary>
public static class LossyLinkSocket
{
    /// <summary>The retransmission timeout floor asked for, microseconds (the kernel accepts 2 ms to 200 ms).</summary>
    public const int RtoMinMicroseconds = 10_000;

    private const int TcpThinLinearTimeouts = 16; // linux/tcp.h
    private const int TcpRtoMinUs = 45;           // linux/tcp.h, Linux 6.15
    private const int IpProtoTcp = 6;             // IPPROTO_TCP

    private static readonly ILogger Log = Serilog.Log.ForContext(typeof(LossyLinkSocket));

    /// <summary>Applies the options a TCP socket to a controller gets; returns how many the system accepted.</summary>
    public static int Tune(Socket socket)
    {
        ArgumentNullException.ThrowIfNull(socket);
        if (!OperatingSystem.IsLinux())
        {
            return 0;
        }

        var applied = 0;
        applied += TrySet(socket, TcpThinLinearTimeouts, 1, "TCP_THIN_LINEAR_TIMEOUTS");
        applied += TrySet(socket, TcpRtoMinUs, RtoMinMicroseconds, "TCP_RTO_MIN_US");
        return applied;
    }

    /// <summary>Reads a TCP option back as the kernel holds it (Linux); null where it is not there.</summary>
    public static int? Read(Socket socket, int option)
    {
        ArgumentNullException.ThrowIfNull(socket);
        if (!OperatingSystem.IsLinux())
        {
            return null;
        }

        Span<byte> value = stackalloc byte[sizeof(int)];
        try
        {
            return socket.GetRawSocketOption(IpProtoTcp, option, value) == sizeof(int) ? BitConverter.ToInt32(value) : null;
        }
        catch (SocketException)
        {
            return null;
        }
    }

    /// <summary>TCP_THIN_LINEAR_TIMEOUTS (linux/tcp.h).</summary>
    public const int ThinLinearTimeoutsOption = TcpThinLinearTimeouts;

    /// <summary>TCP_RTO_MIN_US (linux/tcp.h, Linux 6.15).</summary>
    public const int RtoMinOption = TcpRtoMinUs;

    // Raw options: SocketOptionName's numbers are .NET's own and are translated per system (16 at the TCP level is
    // TcpKeepAliveRetryCount, i.e. TCP_KEEPCNT), so Linux's numbers must go through the raw call unchanged.
    private static int TrySet(Socket socket, int option, int value, string name)
    {
        try
        {
            socket.SetRawSocketOption(IpProtoTcp, option, BitConverter.GetBytes(value));
            return 1;
        }
        catch (SocketException e)
        {
            Log.Debug("{Option} not available here ({Error}): the kernel's default stays", name, e.SocketErrorCode);
            return 0;
        }
    }
}
