using System.Diagnostics;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>
/// A pty pair made by socat (<c>socat -d -d pty,raw,echo=0,link=A pty,raw,echo=0,link=B</c>): the simulator serves
/// one end, the serial transport opens the other, as a null-modem cable would join them.
/// </summary>
internal sealed class SocatPair : IDisposable
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

    public string A { get; }

    public string B { get; }

    /// <summary>Null (and why) when socat is not installed.</summary>
    public static SocatPair? TryStart(out string why)
    {
        var socat = new[] { "/usr/bin/socat", "/bin/socat", "/usr/local/bin/socat" }.FirstOrDefault(File.Exists);
        if (socat is null)
        {
            why = "socat is not installed (.ci/run installs it): serial transport test skipped";
            return null;
        }

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

        why = File.Exists(pair.A) && File.Exists(pair.B) ? string.Empty : "socat did not create the pty links";
        if (why.Length > 0)
        {
            pair.Dispose();
            return null;
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
