using System.Diagnostics;
using System.Text.RegularExpressions;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>`pmacstream sim` run as a real process (the CLI assembly beside the tests), stopped with SIGTERM.</summary>
internal sealed partial class SimProcess : IDisposable
{
    private readonly Process _process;
    private readonly List<string> _output = [];

    private SimProcess(Process process)
    {
        _process = process;
    }

    public int Port { get; private set; }

    public IReadOnlyList<string> Output
    {
        get
        {
            lock (_output)
            {
                return [.. _output];
            }
        }
    }

    public static SimProcess Start(params string[] args)
    {
        var dll = Path.Combine(AppContext.BaseDirectory, "pmacstream.dll");
        var psi = new ProcessStartInfo("dotnet") { RedirectStandardOutput = true, RedirectStandardError = true, UseShellExecute = false };
        psi.ArgumentList.Add(dll);
        psi.ArgumentList.Add("sim");
        foreach (var a in args)
        {
            psi.ArgumentList.Add(a);
        }

        var sim = new SimProcess(Process.Start(psi)!);
        var ready = new TaskCompletionSource();
        sim._process.OutputDataReceived += (_, e) =>
        {
            if (e.Data is null)
            {
                ready.TrySetResult();
                return;
            }

            lock (sim._output)
            {
                sim._output.Add(e.Data);
            }

            var m = PortLine().Match(e.Data);
            if (m.Success)
            {
                sim.Port = int.Parse(m.Groups[1].Value, System.Globalization.CultureInfo.InvariantCulture);
            }

            if (e.Data.StartsWith("pmacstream sim: listening", StringComparison.Ordinal) || e.Data.StartsWith("pmacstream sim: serving", StringComparison.Ordinal))
            {
                ready.TrySetResult();
            }
        };
        sim._process.ErrorDataReceived += (_, e) =>
        {
            if (e.Data is not null)
            {
                lock (sim._output)
                {
                    sim._output.Add(e.Data);
                }
            }
        };
        sim._process.BeginOutputReadLine();
        sim._process.BeginErrorReadLine();
        if (!ready.Task.Wait(TimeSpan.FromSeconds(30)))
        {
            sim.Dispose();
            throw new TimeoutException("pmacstream sim did not start: " + string.Join('\n', sim.Output));
        }

        return sim;
    }

    /// <summary>Sends SIGTERM and returns the exit code.</summary>
    public int Terminate()
    {
        if (!_process.HasExited)
        {
            Process.Start("kill", ["-TERM", _process.Id.ToString(System.Globalization.CultureInfo.InvariantCulture)])!.WaitForExit();
        }

        if (!_process.WaitForExit(15000))
        {
            _process.Kill();
            throw new TimeoutException("pmacstream sim did not stop on SIGTERM");
        }

        _process.WaitForExit();
        return _process.ExitCode;
    }

    public void Dispose()
    {
        if (!_process.HasExited)
        {
            _process.Kill();
            _process.WaitForExit(5000);
        }

        _process.Dispose();
    }

    [GeneratedRegex(@"listening on tcp .*\(port (\d+)\)")]
    private static partial Regex PortLine();
}
