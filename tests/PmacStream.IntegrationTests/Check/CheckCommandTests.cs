using System.Diagnostics;
using System.Text;
using System.Text.Json;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Check;

/// <summary>`pmacstream check`: output formats, exit codes, hostile files. Tests in this class share the output hook, so they run in sequence.</summary>
public sealed class CheckCommandTests : IDisposable
{
    private readonly TestFolder _temp = new("check");

    public void Dispose()
    {
        Microsoft.Data.Sqlite.SqliteConnection.ClearAllPools();
        _temp.Dispose();
    }

    private string Write(string name, byte[] bytes)
    {
        var path = Path.Combine(_temp.Path, name);
        File.WriteAllBytes(path, bytes);
        return path;
    }

    private string Write(string name, string text) => Write(name, Encoding.UTF8.GetBytes(text));

    /// <summary>Runs the command in process through the real parser and error handling; returns exit code and stdout.</summary>
    /// <summary>Runs the command in process through the real parser and error handling; returns exit code and stdout.</summary>
    private static (int Code, string Output) Run(params string[] args)
    {
        try
        {
            var (code, output, _) = CliRun.InProcess(["check", .. args]);
            return (code, output);
        }
        finally
        {
            DiagnosticText.Culture = System.Globalization.CultureInfo.CurrentUICulture;
        }
    }

    [Fact]
    public void Clean_program_exits_0_with_the_summary_line()
    {
        var (code, output) = Run(RepoRoot.DemoProgram, "--lang", "en");
        code.Should().Be(0);
        output.Trim().Should().MatchRegex(@"^0 errors, 0 warnings, \d+ blocks$");
    }

    [Fact]
    public void Errors_print_file_line_col_and_exit_1()
    {
        var file = Write("bad.nc", "O1\nG00 X1\nG00 G01 X2 F100\nN5\n");
        var (code, output) = Run(file, "--lang", "en");
        code.Should().Be(1);
        var lines = output.TrimEnd().Split('\n').Select(l => l.TrimEnd('\r')).ToArray();
        lines.Should().Contain($"{file}:3:5: error E109: G00 and G01 are both in modal group 01: only one code of a group per block");
        lines.Should().Contain(l => l.StartsWith($"{file}:4:1: error E110: "));
        lines[^1].Should().Be("2 errors, 2 warnings, 3 blocks");   // W002 for lines 2 and 3 once N5 shows the program numbers blocks
        lines[0].Should().Be($"{file}:2:1: warning W002: block has no sequence number while other blocks are numbered");
    }

    [Fact]
    public void Chinese_output_is_Chinese_to_the_last_line()
    {
        var file = Write("zh.nc", "O1\nT1 M41\nG01 X1\nG05\n");
        var (code, output) = Run(file, "--lang", "zh-CN");
        code.Should().Be(1);
        var lines = output.TrimEnd().Split('\n').Select(l => l.TrimEnd('\r')).ToArray();
        lines.Should().HaveCount(4).And.OnlyContain(l => System.Text.RegularExpressions.Regex.IsMatch(l, @"\p{IsCJKUnifiedIdeographs}"));
        lines[^1].Should().Be("2 个错误，1 个警告，3 个程序段");
        Run(file, "--lang", "en").Output.TrimEnd().Split('\n')[^1].Should().Be("2 errors, 1 warnings, 3 blocks");
    }

    [Fact]
    public void Json_output_is_one_object_with_counts_and_diagnostics()
    {
        var file = Write("bad.nc", "O1\nG01 X1\nM50\nM41\n");
        var (code, output) = Run(file, "--json", "--lang", "zh-CN");
        code.Should().Be(1);
        using var doc = JsonDocument.Parse(output);
        var root = doc.RootElement;
        root.EnumerateObject().Select(p => p.Name).Should().Equal("file", "blocks", "errors", "warnings", "diagnostics", "notYetCodes");
        root.GetProperty("file").GetString().Should().Be(file);
        root.GetProperty("blocks").GetInt64().Should().Be(3);
        root.GetProperty("notYetCodes").GetProperty("M41").GetInt32().Should().Be(4);
        root.GetProperty("errors").GetInt32().Should().Be(2);
        var d = root.GetProperty("diagnostics")[0];
        d.EnumerateObject().Select(p => p.Name).Should().Equal("severity", "code", "line", "column", "message");
        d.GetProperty("code").GetString().Should().Be("E116");
        d.GetProperty("severity").GetString().Should().Be("error");
        d.GetProperty("line").GetInt32().Should().Be(2);
        d.GetProperty("message").GetString().Should().Contain("进给");
    }

    [Fact]
    public void Db_option_stores_every_block()
    {
        var db = Path.Combine(_temp.Path, "store.db");
        var demo = RepoRoot.DemoProgram;
        var (code, output) = Run(demo, "--db", db);
        code.Should().Be(0);
        var blocks = long.Parse(output.Trim().Split(' ')[^2]);
        using var store = ProgramStore.Open(db);
        var program = store.ListPrograms().Should().ContainSingle().Subject;
        program.Blocks.Should().Be(blocks);
        store.ReadBlocks(program.Id).LongCount().Should().Be(blocks);
    }

    [Fact]
    public void Db_option_appends_to_an_existing_store_and_leaves_nothing_when_it_cannot_write()
    {
        var db = Path.Combine(_temp.Path, "store.db");
        var demo = RepoRoot.DemoProgram;
        Run(demo, "--db", db).Code.Should().Be(0);
        Run(Write("bad.nc", "O1\nG01 X1\n"), "--db", db).Code.Should().Be(1, "the program has an error, and is still stored");
        using (var store = ProgramStore.Open(db))
        {
            store.ListPrograms().Select(p => p.Errors).Should().Equal(1, 0);
        }

        // A database in a folder that does not exist: exit 2, and no temporary file anywhere in the work folder.
        var before = Directory.GetFiles(_temp.Path, "*", SearchOption.AllDirectories).Order().ToList();
        Run(demo, "--db", Path.Combine(_temp.Path, "no-such-dir", "x.db")).Code.Should().Be(2);
        Directory.GetFiles(_temp.Path, "*", SearchOption.AllDirectories).Order().Should().Equal(before);
    }

    [Fact]
    public void Usage_and_io_problems_exit_2()
    {
        Run(Path.Combine(_temp.Path, "missing.nc")).Code.Should().Be(2);
        Run(_temp.Path).Code.Should().Be(2);
        var ok = Write("ok.nc", "O1\nG00 X1\n");
        Run(ok, "--lang", "fr").Code.Should().Be(2);
        Run(ok, "--profile", Write("bad-profile.json", "{ nope")).Code.Should().Be(2);
        Run(ok, "--profile", Path.Combine(_temp.Path, "no-profile.json")).Code.Should().Be(2);
        Run(ok, "--db", _temp.Path).Code.Should().Be(2);
        Run().Code.Should().Be(2);
        Run(ok).Code.Should().Be(0);
    }

    [Fact]
    public void A_custom_profile_changes_what_is_known()
    {
        // paper-24g7m's set plus a tool change, as a machine's own profile file.
        var json = MachineProfile.Paper.ToJson().Replace("{\n      \"code\": \"M00\"", "{ \"code\": \"M06\", \"group\": \"MA\", \"description\": \"tool change\" },\n    {\n      \"code\": \"M00\"");
        json.Should().Contain("M06");
        var profile = Write("p.json", json);
        var file = Write("tc.nc", "O1\nT2 M06\n");
        Run(file, "--profile", "paper-24g7m").Code.Should().Be(1);
        var (code, output) = Run(file, "--profile", profile, "--lang", "en");
        code.Should().Be(0);
        output.Should().Contain("W006: M06 (tool change) is accepted by profile 'paper-24g7m' but the controller cannot run it yet",
            "a code a profile file does not mark as run by the library is not yet");
        Run(file).Code.Should().Be(0, "the default profile knows M06");
        Run(file, "--profile", "grbl").Code.Should().Be(1, "grbl has no tool changer");
    }

    // Theory data carries only names: xunit serializes theory data for the test runner at discovery, and a 10 MB
    // byte array there cost gigabytes of test-host memory (the host was OOM-killed on a loaded machine).
    public static TheoryData<string, string> Hostile => new()
    {
        { "empty.nc", "E120" },
        { "binary.bin", "E121" },
        { "nul.nc", "E121" },
        { "utf16.nc", "E122" },
        { "comment.nc", "E103" },
        { "longline.nc", "E114" },
    };

    private static byte[] HostileBytes(string name) => name switch
    {
        "empty.nc" => [],
        "binary.bin" => Enumerable.Range(0, 4096).Select(i => (byte)((i * 7919) % 256)).ToArray(),
        "nul.nc" => Encoding.ASCII.GetBytes("O1\nG00 X1\0Y2\n"),
        "utf16.nc" => Encoding.Unicode.GetPreamble().Concat(Encoding.Unicode.GetBytes("O1\nG00 X1\n")).ToArray(),
        "comment.nc" => Encoding.ASCII.GetBytes("O1\nG00 X1 (never closed\n"),
        "longline.nc" => Encoding.ASCII.GetBytes("O1\nG00 X1 (" + new string('x', 10 * 1024 * 1024) + ")\n"),
        _ => throw new ArgumentOutOfRangeException(nameof(name), name, "no such hostile file"),
    };

    [Theory]
    [MemberData(nameof(Hostile))]
    public void Hostile_files_give_a_clear_diagnostic_and_exit_1(string name, string code)
    {
        var file = Write(name, HostileBytes(name));
        var (exit, output) = Run(file, "--lang", "en");
        exit.Should().Be(1);
        output.Should().Contain($": error {code}: ");
        output.Should().NotContain("   at ");
    }

    [Fact]
    public void Cr_only_program_checks_clean()
    {
        var text = File.ReadAllText(RepoRoot.DemoProgram).Replace("\r\n", "\n").Replace('\n', '\r');
        var (code, output) = Run(Write("cr.nc", text));
        code.Should().Be(0);
        output.Should().StartWith("0 errors, 0 warnings");
    }

    [Fact]
    public async Task The_real_process_reports_hostile_input_without_a_stack_trace()
    {
        var cli = Path.Combine(AppContext.BaseDirectory, "pmacstream.dll");
        File.Exists(cli).Should().BeTrue();
        foreach (var (args, expected) in new[] { ((string[])[Write("nul2.nc", "G00\0\0X1")], 1), ([Path.Combine(_temp.Path, "nope.nc")], 2) })
        {
            var psi = new ProcessStartInfo("dotnet") { RedirectStandardOutput = true, RedirectStandardError = true };
            psi.ArgumentList.Add(cli);
            psi.ArgumentList.Add("check");
            foreach (var a in args)
            {
                psi.ArgumentList.Add(a);
            }

            using var p = Process.Start(psi)!;
            var stdoutTask = p.StandardOutput.ReadToEndAsync();
            var stderr = await p.StandardError.ReadToEndAsync();
            var stdout = await stdoutTask;
            await p.WaitForExitAsync();
            p.ExitCode.Should().Be(expected, stderr);
            (stdout + stderr).Should().NotContain("   at ").And.NotContain("Exception");
            if (expected == 2)
            {
                stderr.Should().Contain("no such file");
            }
        }
    }
}
