using System.Text.Json;

namespace PmacStream.IntegrationTests.Console;

/// <summary>
/// The console's read-only commands and the store's program commands as command lines in process, through the parser
/// and their handlers (<c>status</c>, <c>alarms</c>, <c>offsets</c>, <c>tools</c> on the built-in simulator;
/// <c>programs import/list/show/export/rm/start</c> on an SQLite store): the text and <c>--json</c> shapes the README
/// shows, the exit codes, and the usage errors the handlers raise before any controller is opened.
/// </summary>
public sealed class ConsoleHandlerTests : IDisposable
{
    private readonly TestFolder _folder = new("handlers");

    public void Dispose() => _folder.Dispose();

    private string[] Sim => ["--sim", "--job-db", Path.Combine(_folder.Path, "jobs.db"), "--tables", Path.Combine(_folder.Path, "tables.json")];

    [Fact]
    public void Status_alarms_offsets_and_tools_print_their_json_on_the_built_in_simulator()
    {
        var status = Ok(["status", "--json", .. Sim]).Trim();
        status.Split('\n').Should().ContainSingle("one sample without --watch");
        using (var doc = JsonDocument.Parse(status))
        {
            doc.RootElement.GetProperty("axes").EnumerateArray().Select(a => a.GetProperty("name").GetString()).Should().Contain(["X", "Y", "Z"]);
            doc.RootElement.GetProperty("alarms").GetArrayLength().Should().Be(0);
        }

        Ok(["status", .. Sim]).Should().Contain("axis  homed     machine        work       to go");
        Ok(["alarms", "--json", .. Sim]).Trim().Should().Be("{\"alarms\":[]}");
        Ok(["alarms", .. Sim]).Should().Be("no active alarm\n");
        using (var offsets = JsonDocument.Parse(Ok(["offsets", "--json", .. Sim])))
        {
            offsets.RootElement.GetProperty("active").GetString().Should().Be("G54");
            offsets.RootElement.GetProperty("offsets").EnumerateArray().Select(o => o.GetProperty("name").GetString()).Should().StartWith(["G54", "G55"]);
        }

        using (var tools = JsonDocument.Parse(Ok(["tools", "--json", .. Sim])))
        {
            tools.RootElement.GetProperty("tools").ValueKind.Should().Be(JsonValueKind.Array);
        }
    }

    [Fact]
    public void Usage_errors_of_the_handlers_exit_2_before_a_controller_is_opened()
    {
        Usage(["status", "--interval", "0.01", .. Sim]).Should().Contain("--interval must be between 0.05 and 3600 seconds");
        Usage(["offsets", "set", "G55", "Q5", .. Sim]).Should().Contain("offsets set G55: give X, Y and/or Z values once each");
        Usage(["offsets", "set", "G54", "X1", "--touch", "X0", .. Sim]).Should().Contain("--touch sets one axis");
        Usage(["tools", "set", "3", .. Sim]).Should().Contain("tools set 3: give --length, --radius");
        Usage(["tools", "set", "3", "--touch", "X0", .. Sim]).Should().Contain("--touch measures the length from Z");
        Usage(["mdi", "G0 X1"]).Should().Contain("say which controller");
    }

    [Fact]
    public void Programs_import_list_show_export_start_and_rm_run_in_process()
    {
        var store = "sqlite:" + Path.Combine(_folder.Path, "store.db");
        var source = Path.Combine(_folder.Path, "part.nc");
        const string text = "G21 G90 G17\nG00 X0 Y0 Z5\nG01 Z-1 F300\nG01 X10 Y5\nG01 X20\nM30\n";
        File.WriteAllText(source, text);

        var id = Ok("programs", "import", source, "--store", store).Trim();
        long.TryParse(id, out _).Should().BeTrue($"import prints only the revision's id, not '{id}'");
        using (var list = JsonDocument.Parse(Ok("programs", "list", "--json", "--store", store)))
        {
            list.RootElement.EnumerateArray().Should().ContainSingle(p => p.GetProperty("id").GetRawText() == id);
        }

        Ok("programs", "show", id, "--store", store).Should().StartWith($"program {id}: ").And.Contain("  sha256    ");
        Ok("programs", "export", id, "--store", store).Should().Be(text, "export writes the exact source");
        var start = CliRun.InProcess("programs", "start", id, "--from-line", "4", "--store", store);
        start.Code.Should().Be(0, start.Err);
        start.Out.Should().StartWith("start at line 4");
        start.Err.Should().Contain("planned from the store");
        Ok("programs", "rm", id, "--store", store).Should().Be($"removed program {id}\n");
        var gone = CliRun.InProcess("programs", "show", id, "--store", store);
        gone.Code.Should().Be(2);
        gone.Err.Should().Contain($"no program {id}");
    }

    private static string Ok(params string[] args)
    {
        var (code, stdout, stderr) = CliRun.InProcess(args);
        code.Should().Be(0, $"pmacstream {string.Join(' ', args)}; stderr: {stderr}");
        return stdout.ReplaceLineEndings("\n");
    }

    private static string Usage(params string[] args)
    {
        var (code, stdout, stderr) = CliRun.InProcess(args);
        code.Should().Be(2, $"pmacstream {string.Join(' ', args)}; stdout: {stdout}");
        return stderr;
    }
}
