using System.Runtime.InteropServices;

namespace PmacStream.Testing;

/// <summary>POSIX signals to a process: what an operator's Ctrl+C, a service stop or a kill does to the CLI.</summary>
public static partial class PosixSignals
{
    /// <summary>SIGINT (Ctrl+C).</summary>
    public const int SigInt = 2;

    /// <summary>SIGKILL (no handler runs).</summary>
    public const int SigKill = 9;

    /// <summary>SIGTERM (a service stop).</summary>
    public const int SigTerm = 15;

    /// <summary>Sends <paramref name="signal"/> to process <paramref name="pid"/>; 0 when it was sent.</summary>
    public static int Send(int pid, int signal) => Kill(pid, signal);

    [LibraryImport("libc", EntryPoint = "kill", SetLastError = true)]
    private static partial int Kill(int pid, int signal);
}
