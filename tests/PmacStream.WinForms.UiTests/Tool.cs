using System.Diagnostics;

namespace PmacStream.WinForms.UiTests;

/// <summary>Runs a command-line tool (xdotool, xwininfo, ImageMagick, wine) with a bound on its time.</summary>
internal static class Tool
{
    /// <summary>Runs the tool and returns its standard output; throws when it fails or outlives <paramref name="timeout"/>.</summary>
    public static string Run(string file, IEnumerable<string> args, TimeSpan timeout, IDictionary<string, string>? environment = null)
    {
        var (exit, output, error) = TryRun(file, args, timeout, environment);
        if (exit != 0)
        {
            throw new InvalidOperationException($"{file} {string.Join(' ', args)} exited {exit}: {error.Trim()}");
        }

        return output;
    }

    /// <summary>Runs the tool and returns its exit code and output; throws only when it outlives <paramref name="timeout"/>.</summary>
    public static (int Exit, string Output, string Error) TryRun(string file, IEnumerable<string> args, TimeSpan timeout, IDictionary<string, string>? environment = null)
    {
        using var process = new Process { StartInfo = Start(file, args, environment) };
        process.StartInfo.RedirectStandardOutput = true;
        process.StartInfo.RedirectStandardError = true;
        process.Start();
        var output = process.StandardOutput.ReadToEndAsync();
        var error = process.StandardError.ReadToEndAsync();
        if (!process.WaitForExit(timeout))
        {
            process.Kill(entireProcessTree: true);
            throw new TimeoutException($"{file} {string.Join(' ', args)} did not finish within {timeout.TotalSeconds:0} s");
        }

        process.WaitForExit();
        return (process.ExitCode, output.Result, error.Result);
    }

    /// <summary>Start information without a shell, with extra environment variables.</summary>
    public static ProcessStartInfo Start(string file, IEnumerable<string> args, IDictionary<string, string>? environment = null)
    {
        var info = new ProcessStartInfo(file) { UseShellExecute = false };
        foreach (var a in args)
        {
            info.ArgumentList.Add(a);
        }

        foreach (var (key, value) in environment ?? new Dictionary<string, string>())
        {
            info.Environment[key] = value;
        }

        return info;
    }
}
