using System.Diagnostics;

namespace PmacStream.Testing;

/// <summary>
/// A pty pair made by socat (<c>socat -d -d pty,raw,echo=0,link=A pty,raw,echo=0,link=B</c>): the simulator serves
/// one end, the serial transport opens the other, as a null-modem cable would join them.
/// </summary>
public sealed class SocatPair : IDisposable
{
    private readonly Process _process;
    private readonly string _dir;

    private SocatPair(Process process, string dir)
    {
        _process = process;
        _dir = dir;
        A = Path.Combine(dir, "A");
        B = Path.Combine(dir, "B");
    }

    /// <summary>One end (the simulator's, in these tests).</summary>
    public string A { get; }

    /// <summary>The other end (the host's).</summary>
    public string B { get; }

    /// <summary>
    /// Starts socat. Reports SKIPPED when socat is not on PATH (<see cref="Requires.Socat"/>); throws when socat is
    /// there but makes no pty pair, which is a failure.
    /// </summary>
    public static SocatPair Start()
    {
        var socat = Requires.Socat();
        var dir = Directory.CreateTempSubdirectory("pmacstream-pty-").FullName;
        var psi = new ProcessStartInfo(socat)
        {
            RedirectStandardError = true,
            RedirectStandardOutput = true,
            UseShellExecute = false,
        };
        foreach (var a in new[] { "-d", "-d", $"pty,raw,echo=0,link={dir}/A", $"pty,raw,echo=0,link={dir}/B" })
        {
            psi.ArgumentList.Add(a);
        }

        var p = Process.Start(psi)!;
        p.ErrorDataReceived += (_, _) => { };
        p.BeginErrorReadLine();
        p.BeginOutputReadLine();
        var pair = new SocatPair(p, dir);
        for (var i = 0; i < 500 && !(File.Exists(pair.A) && File.Exists(pair.B)); i++)
        {
            Thread.Sleep(10);
        }

        if (!(File.Exists(pair.A) && File.Exists(pair.B)))
        {
            pair.Dispose();
            throw new InvalidOperationException($"{socat} did not create the pty links in {dir} within 5 s");
        }

        return pair;
    }

    /// <summary>Ends socat: both ptys hang up, as when a cable is pulled.</summary>
    public void Kill()
    {
        if (!_process.HasExited)
        {
            _process.Kill();
            _process.WaitForExit(5000);
        }
    }

    /// <summary>Ends socat and removes the links' folder.</summary>
    public void Dispose()
    {
        Kill();
        _process.Dispose();
        try
        {
            Directory.Delete(_dir, true);
        }
        catch (IOException)
        {
        }
    }
}
