using System.Net;
using System.Net.Sockets;
using PmacStream.Pmac;

namespace PmacStream.Core.Tests.Pmac;

/// <summary>
/// The host's TCP tuning for lossy links reaches the kernel under Linux's own option numbers: read back with
/// getsockopt, not trusted from the set call (an option number passed through .NET's SocketOptionName is translated
/// to another option: 16 became TCP_KEEPCNT).
/// </summary>
public sealed class LossyLinkSocketTests
{
    [SkippableFact]
    public void Thin_linear_timeouts_and_the_retransmission_floor_are_what_the_kernel_holds()
    {
        Skip.IfNot(OperatingSystem.IsLinux(), "Linux TCP options");
        using var listener = new TcpListener(IPAddress.Loopback, 0);
        listener.Start();
        using var socket = new Socket(SocketType.Stream, ProtocolType.Tcp);
        socket.Connect((IPEndPoint)listener.LocalEndpoint);
        var keepCount = socket.GetSocketOption(SocketOptionLevel.Tcp, SocketOptionName.TcpKeepAliveRetryCount);

        var applied = LossyLinkSocket.Tune(socket);

        LossyLinkSocket.Read(socket, LossyLinkSocket.ThinLinearTimeoutsOption).Should().Be(1);
        socket.GetSocketOption(SocketOptionLevel.Tcp, SocketOptionName.TcpKeepAliveRetryCount).Should().Be(keepCount, "keep-alive is not touched");
        var floor = LossyLinkSocket.Read(socket, LossyLinkSocket.RtoMinOption);
        Skip.If(floor is null && applied == 1, $"this kernel ({Environment.OSVersion.Version}) has no TCP_RTO_MIN_US (Linux 6.15+)");
        // The kernel keeps it in jiffies (10 ms is 12 ms at HZ=250): far below the 200 ms default either way.
        floor.Should().BeInRange(LossyLinkSocket.RtoMinMicroseconds, LossyLinkSocket.RtoMinMicroseconds + 10_000);
        applied.Should().Be(2);
    }
}
