using System.Diagnostics;

namespace PmacStream.WinForms.UiTests;

/// <summary>A private X server (Xvfb) with no window manager, on a display no other server uses.</summary>
internal sealed class XServer : IDisposable
{
    /// <summary>Screen size: room for the 1280x982 form and a dialog beside it.</summary>
    public const int Width = 1920, Height = 1080;

    private readonly Process _process;

    private XServer(Process process, string display)
    {
        _process = process;
        Display = display;
    }

    /// <summary>The DISPLAY value, e.g. <c>:93</c>.</summary>
    public string Display { get; }

    /// <summary>Starts Xvfb on the first free display from :90 and waits (bounded) for its socket.</summary>
    public static XServer Start()
    {
        for (var n = 90; n < 140; n++)
        {
            if (File.Exists($"/tmp/.X{n}-lock") || File.Exists($"/tmp/.X11-unix/X{n}"))
            {
                continue;
            }

            var process = Process.Start(Tool.Start("Xvfb", [$":{n}", "-screen", "0", $"{Width}x{Height}x24", "-nolisten", "tcp"]))!;
            var deadline = Stopwatch.StartNew();
            while (deadline.Elapsed < TimeSpan.FromSeconds(15) && !process.HasExited)
            {
                if (File.Exists($"/tmp/.X11-unix/X{n}"))
                {
                    return new XServer(process, $":{n}");
                }

                Thread.Sleep(50);
            }

            if (!process.HasExited)
            {
                process.Kill();
            }

            process.Dispose();
        }

        throw new InvalidOperationException("Xvfb did not start on any display from :90 to :139");
    }

    /// <inheritdoc />
    public void Dispose()
    {
        // SIGTERM lets Xvfb remove its lock file and socket; SIGKILL only if it does not go.
        if (!_process.HasExited)
        {
            Tool.TryRun("kill", ["-TERM", _process.Id.ToString(System.Globalization.CultureInfo.InvariantCulture)], TimeSpan.FromSeconds(10));
            if (!_process.WaitForExit(5000))
            {
                _process.Kill();
                _process.WaitForExit(5000);
            }
        }

        _process.Dispose();
    }
}
