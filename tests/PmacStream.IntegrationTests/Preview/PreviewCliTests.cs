using System.Buffers.Binary;
using PmacStream.Cli;
using PmacStream.Cli.Commands;

namespace PmacStream.IntegrationTests.Preview;

/// <summary>
/// `pmacstream preview` in process, through its handler (<see cref="PreviewCommand.RunAsync"/>, the options bound into
/// <see cref="PreviewArgs"/>): the picture it writes, its exit codes, and the executed-log report.
/// </summary>
public sealed class PreviewCliTests : IDisposable
{
    private readonly TestFolder _temp = new("preview-cli");

    public void Dispose() => _temp.Dispose();

    private string Program(string text)
    {
        var path = Path.Combine(_temp.Path, "part.nc");
        File.WriteAllText(path, text);
        return path;
    }

    /// <summary>The handler's exit code and what it wrote; a usage or I/O error as the command line reports it (its code, its message on stderr).</summary>
    private static (int Code, string Stdout, string Stderr) Run(string file, string png, string size = "1200x900", string? executed = null, string? lang = null)
    {
        var stdout = new StringWriter();
        var stderr = new StringWriter();
        try
        {
            var code = PreviewCommand.RunAsync(new PreviewArgs(file, png, size, "xy", executed, lang, null, false), new CliConsole(stdout, stderr), CancellationToken.None)
                .GetAwaiter().GetResult();
            return (code, stdout.ToString(), stderr.ToString());
        }
        catch (CliException e)
        {
            return (e.ExitCode, stdout.ToString(), stderr + "pmacstream preview: " + e.Message);
        }
    }

    private const string Square = "G21 G17 G90\nG00 X0 Y0\nG01 X10 F300\nY10\nX0\nY0\nM30\n";

    [Fact]
    public void Writes_a_png_of_the_requested_size()
    {
        var png = Path.Combine(_temp.Path, "out.png");
        var (code, stdout, stderr) = Run(Program(Square), png, size: "320x200");

        code.Should().Be(0, stderr);
        var bytes = File.ReadAllBytes(png);
        bytes.Take(8).Should().Equal(new byte[] { 0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A });
        BinaryPrimitives.ReadInt32BigEndian(bytes.AsSpan(16)).Should().Be(320, "IHDR width");
        BinaryPrimitives.ReadInt32BigEndian(bytes.AsSpan(20)).Should().Be(200, "IHDR height");
        stdout.Should().Contain("X 0 .. 10");
    }

    [Fact]
    public void Chinese_legend_is_asked_for_with_lang_and_an_unknown_language_is_a_usage_error()
    {
        var png = Path.Combine(_temp.Path, "zh.png");
        var (code, stdout, stderr) = Run(Program(Square), png, lang: "zh-CN");
        code.Should().Be(0, stderr);
        File.Exists(png).Should().BeTrue(stdout);
        // Without a font with Chinese glyphs the legend is English and the command says why.
        if (stderr.Length > 0)
        {
            stderr.Should().Contain("warning").And.Contain("fonts-noto-cjk");
        }

        var bad = Path.Combine(_temp.Path, "fr.png");
        (code, _, stderr) = Run(Program(Square), bad, lang: "fr");
        code.Should().Be(2);
        stderr.Should().Contain("--lang fr: expected en or zh-CN");
        File.Exists(bad).Should().BeFalse("nothing is written for a bad command line");
    }

    [Fact]
    public void Missing_program_is_a_usage_error_and_writes_nothing()
    {
        var png = Path.Combine(_temp.Path, "none.png");
        var (code, _, stderr) = Run(Path.Combine(_temp.Path, "missing.nc"), png);

        code.Should().Be(2);
        stderr.Should().Contain("missing.nc");
        File.Exists(png).Should().BeFalse();
    }

    [Fact]
    public void Executed_log_with_a_skipped_line_is_reported_and_fails()
    {
        var log = Path.Combine(_temp.Path, "executed.csv");
        // Lines 2..6 move; line 4 never ran.
        File.WriteAllText(log, "sequence,line,start_s,end_s,x,y,z,kind\n1,2,0,1,0,0,0,Rapid\n2,3,1,2,10,0,0,Linear\n3,5,2,3,0,10,0,Linear\n4,6,3,4,0,0,0,Linear\n");
        var (code, stdout, stderr) = Run(Program(Square), Path.Combine(_temp.Path, "x.png"), executed: log);

        code.Should().Be(1, stdout + stderr);
        (stdout + stderr).Should().MatchRegex("(?s)never.*\\b4\\b");
    }
}
