using System.Diagnostics;

namespace PmacStream.WinForms.UiTests;

/// <summary>
/// The published HMI running under Wine on a given X display, with its UI-test channel and job store in a
/// folder of the test's own. Wine keeps its built-in <c>mscoree</c> (overriding it, as Wine-Mono setups do,
/// stops .NET from loading); W^X is off because under Wine the runtime otherwise dies freeing dynamic methods
/// ("Internal CLR error" in <c>DynamicResolver.DestroyScout.Finalize</c>).
/// </summary>
internal sealed class WineHmi : IDisposable
{
    private readonly Process _process;
    private readonly Dictionary<string, string> _environment;

    private WineHmi(Process process, Dictionary<string, string> environment)
    {
        _process = process;
        _environment = environment;
    }

    /// <summary>The Wine prefix the test uses, kept between runs (creating one takes a while the first time).</summary>
    public static string Prefix =>
        Environment.GetEnvironmentVariable("PMACSTREAM_WINEPREFIX") is { Length: > 0 } p
            ? p
            : Path.Combine(Environment.GetFolderPath(Environment.SpecialFolder.UserProfile), ".cache", "pmacstream", "wine-prefix");

    /// <summary>True once the HMI process has ended.</summary>
    public bool HasExited => _process.HasExited;

    /// <summary>A Linux path as the Windows program sees it (Wine maps <c>Z:</c> to <c>/</c>).</summary>
    public static string WindowsPath(string linuxPath) => "Z:" + Path.GetFullPath(linuxPath).Replace('/', '\\');

    /// <summary>
    /// Creates the prefix when it is missing and gives it the fonts the screen needs; returns how long that took
    /// (zero when an earlier run had done it).
    /// </summary>
    public static TimeSpan EnsurePrefix(string display)
    {
        var marker = Path.Combine(Prefix, "pmacstream-prefix-v1");
        if (File.Exists(marker))
        {
            return TimeSpan.Zero;
        }

        Directory.CreateDirectory(Prefix);
        var clock = Stopwatch.StartNew();
        var environment = BaseEnvironment(display);
        if (!File.Exists(Path.Combine(Prefix, "system.reg")))
        {
            // Only while the prefix is made: no offer to install Wine-Mono or Gecko (neither is needed, and the
            // installer would wait for a click).
            var creating = new Dictionary<string, string>(environment) { ["WINEDLLOVERRIDES"] = "mscoree=;mshtml=" };
            Tool.Run("wineboot", ["--init"], TimeSpan.FromMinutes(5), creating);
        }

        // Windows links its UI fonts to a Chinese font; Wine's Tahoma has no CJK glyphs and linking it breaks GDI+
        // (SystemFonts.DefaultFont throws). So the dialog font (MS Shell Dlg, WinForms' default through the message
        // font) becomes WenQuanYi Micro Hei, which has both scripts, and the lists' monospace font links to it.
        var fonts = Path.Combine(Path.GetTempPath(), $"pmacstream-wine-fonts-{Environment.ProcessId}.reg");
        File.WriteAllText(fonts, """
            REGEDIT4

            [HKEY_LOCAL_MACHINE\Software\Microsoft\Windows NT\CurrentVersion\FontSubstitutes]
            "MS Shell Dlg"="WenQuanYi Micro Hei"
            "MS Shell Dlg 2"="WenQuanYi Micro Hei"

            [HKEY_LOCAL_MACHINE\Software\Microsoft\Windows NT\CurrentVersion\FontLink\SystemLink]
            "Liberation Mono"=hex(7):77,71,79,2d,6d,69,63,72,6f,68,65,69,2e,74,74,63,2c,57,65,6e,51,75,61,6e,59,69,20,4d,69,63,72,6f,20,48,65,69,00,00

            """);
        try
        {
            Tool.Run("wine", ["regedit", "/S", WindowsPath(fonts)], TimeSpan.FromMinutes(2), environment);
            Tool.Run("wineserver", ["-w"], TimeSpan.FromMinutes(2), environment);
        }
        finally
        {
            File.Delete(fonts);
        }

        File.WriteAllText(marker, "prefix created and its fonts set by the PmacStream UI test\n");
        return clock.Elapsed;
    }

    /// <summary>Starts the HMI with the built-in simulator's clock at <paramref name="simSpeed"/>.</summary>
    public static WineHmi Start(string exe, string display, string channelDirectory, string jobDatabase, string simSpeed)
    {
        var environment = BaseEnvironment(display);
        environment["PMACSTREAM_JOB_DB"] = WindowsPath(jobDatabase);
        var process = Process.Start(Tool.Start("wine", [exe, "--sim-speed", simSpeed, "--ui-test", WindowsPath(channelDirectory)], environment))!;
        return new WineHmi(process, environment);
    }

    /// <summary>Waits (bounded) for the HMI to end by itself.</summary>
    public bool WaitForExit(TimeSpan timeout) => _process.WaitForExit(timeout);

    /// <inheritdoc />
    public void Dispose()
    {
        if (!_process.HasExited)
        {
            _process.Kill(entireProcessTree: true);
            _process.WaitForExit(5000);
        }

        // Ends this prefix's wine server (and what it still runs for the HMI); other prefixes are not touched.
        Tool.TryRun("wineserver", ["-k"], TimeSpan.FromSeconds(30), _environment);
        _process.Dispose();
    }

    private static Dictionary<string, string> BaseEnvironment(string display) => new()
    {
        ["DISPLAY"] = display,
        ["WINEPREFIX"] = Prefix,
        ["WINEDEBUG"] = "-all",
        ["WINEDLLOVERRIDES"] = "mshtml=",
        ["DOTNET_EnableWriteXorExecute"] = "0",
        ["LANG"] = "C.UTF-8",
    };
}
