namespace PmacStream.WinForms.UiTests;

/// <summary>
/// Where the UI test finds what it needs: the HMI published for win-x64 and the tools of the
/// screen (wine, Xvfb, xdotool, xwininfo, ImageMagick). <see cref="MissingReason"/> says what is absent.
/// </summary>
internal sealed class UiTestSetup
{
    /// <summary>The tools the test runs, each from its Debian package.</summary>
    public static readonly IReadOnlyList<(string Tool, string Package)> Tools =
    [
        ("wine", "wine"), ("Xvfb", "xvfb"), ("xdotool", "xdotool"), ("xwininfo", "x11-utils"), ("import", "imagemagick"), ("convert", "imagemagick"),
    ];

    /// <summary>Fonts the screen needs under Wine: Latin and Chinese in one (the UI font), and a monospace one.</summary>
    public static readonly IReadOnlyList<(string File, string Package)> Fonts =
    [
        ("/usr/share/fonts/truetype/wqy/wqy-microhei.ttc", "fonts-wqy-microhei"),
        ("/usr/share/fonts/truetype/liberation/LiberationMono-Regular.ttf", "fonts-liberation"),
    ];

    private UiTestSetup(string hmiExe, string? missing)
    {
        HmiExe = hmiExe;
        MissingReason = missing;
    }

    /// <summary>The published PmacStream.WinForms.exe.</summary>
    public string HmiExe { get; }

    /// <summary>Why the test cannot run here, null when it can.</summary>
    public string? MissingReason { get; }

    /// <summary>
    /// True when a missing prerequisite must fail the test instead of skipping it (<c>.ci/run</c> sets
    /// <c>PMACSTREAM_UI_TEST_REQUIRED=1</c> after installing everything and publishing the exe).
    /// </summary>
    public static bool Required => Environment.GetEnvironmentVariable("PMACSTREAM_UI_TEST_REQUIRED") == "1";

    /// <summary>Looks for everything; <c>PMACSTREAM_HMI_EXE</c> overrides the published exe's default place.</summary>
    public static UiTestSetup Find()
    {
        var exe = Environment.GetEnvironmentVariable("PMACSTREAM_HMI_EXE") is { Length: > 0 } e
            ? Path.GetFullPath(e)
            : Path.Combine(RepoRoot.Path, "artifacts", "hmi", "win-x64", "PmacStream.WinForms.exe");
        string? missing = null;
        var tools = Tools.Where(t => PmacStream.Testing.Tools.Find(t.Tool) is null).Select(t => (Name: t.Tool, t.Package))
            .Concat(Fonts.Where(f => !File.Exists(f.File)).Select(f => (Name: f.File, f.Package))).ToList();
        if (!OperatingSystem.IsLinux())
        {
            missing = "the UI test drives Wine under Xvfb, which needs Linux";
        }
        else if (tools.Count > 0)
        {
            missing = $"missing {string.Join(", ", tools.Select(t => t.Name))} (apt-get install {string.Join(' ', tools.Select(t => t.Package).Distinct())})";
        }
        else if (!File.Exists(exe))
        {
            missing = $"{exe} is not there: publish the HMI first (dotnet publish src/PmacStream.WinForms -c Release -r win-x64 --self-contained -o artifacts/hmi/win-x64)";
        }

        return new UiTestSetup(exe, missing);
    }
}
