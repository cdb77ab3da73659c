using System.Diagnostics;
using System.Text;
using System.Text.Json;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Streaming;

/// <summary>
/// The store from the command line, on both engines: <c>programs import</c> prints only the revision's id (the same
/// for the same content), <c>programs list --json</c> and <c>export</c>, <c>stream --program ID</c> runs the stored
/// revision with every block once and in order, and <c>jobs --json</c> shows the job with its outcome and counts.
/// </summary>
public sealed class StoreCliTests : IDisposable
{
    private readonly TestFolder _folder = new("store-cli");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void Import_list_export_stream_by_id_and_the_job_history(string engine)
    {
        var store = Store(engine);
        var source = Path.Combine(_folder.Path, "demo.nc");
        File.WriteAllText(source, $"({Guid.NewGuid():N})\n" + File.ReadAllText(Path.Combine(RepoRoot.Path, "samples", "demo.nc")), new UTF8Encoding(false));

        var (code, stdout, stderr) = Run("programs", "import", source, "--store", store);
        code.Should().Be(0, stderr);
        stdout.Trim().Should().MatchRegex("^[0-9]+$", "import prints only the revision's id");
        var id = long.Parse(stdout.Trim(), System.Globalization.CultureInfo.InvariantCulture);
        Run("programs", "import", source, "--store", store).Out.Trim().Should().Be(id.ToString(System.Globalization.CultureInfo.InvariantCulture), "same content, same profile: same id");

        using (var list = JsonDocument.Parse(Run("programs", "list", "--json", "--store", store).Out))
        {
            var p = list.RootElement.EnumerateArray().Single(e => e.GetProperty("id").GetInt64() == id);
            p.GetProperty("name").GetString().Should().Be("demo.nc");
            p.GetProperty("sha256").GetString().Should().HaveLength(64);
            p.GetProperty("profile").GetString().Should().Be("fanuc-mill");
            p.GetProperty("blocks").GetInt64().Should().BeGreaterThan(3000);
            p.GetProperty("errors").GetInt32().Should().Be(0);
            p.GetProperty("warnings").GetInt32().Should().BeGreaterThanOrEqualTo(0);
            p.GetProperty("imported").GetString().Should().NotBeNullOrEmpty();
        }

        var exported = Path.Combine(_folder.Path, "exported.nc");
        Run("programs", "export", id.ToString(System.Globalization.CultureInfo.InvariantCulture), "--out", exported, "--store", store).Code.Should().Be(0);
        File.ReadAllBytes(exported).Should().Equal(File.ReadAllBytes(source), "export writes the exact source bytes");

        var run = Run("stream", "--program", id.ToString(System.Globalization.CultureInfo.InvariantCulture), "--sim", "--sim-speed", "instant", "--stops", "continue",
            "--station", "station-1", "--machine", "mill-1", "--store", store);
        run.Code.Should().Be(0, run.Out + run.Err);
        var executed = System.Text.RegularExpressions.Regex.Match(run.Out, @"executed (\d+) of (\d+) blocks");
        executed.Success.Should().BeTrue(run.Out);
        executed.Groups[1].Value.Should().Be(executed.Groups[2].Value, "every block once, in order (the demo's own check)");

        using var jobs = JsonDocument.Parse(Run("jobs", "--json", "--store", store).Out);
        var job = jobs.RootElement.EnumerateArray().First(j => j.GetProperty("programId").ValueKind == JsonValueKind.Number && j.GetProperty("programId").GetInt64() == id);
        job.GetProperty("outcome").GetString().Should().Be("completed");
        job.GetProperty("station").GetString().Should().Be("station-1");
        job.GetProperty("machine").GetString().Should().Be("mill-1");
        job.GetProperty("blocksExecuted").GetInt64().Should().Be(long.Parse(executed.Groups[1].Value, System.Globalization.CultureInfo.InvariantCulture));
        job.GetProperty("blocksTotal").GetInt64().Should().Be(long.Parse(executed.Groups[2].Value, System.Globalization.CultureInfo.InvariantCulture));
        job.GetProperty("started").GetString().Should().NotBeNullOrEmpty();
        job.GetProperty("ended").GetString().Should().NotBeNullOrEmpty();
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_program_with_errors_is_stored_its_diagnostics_go_to_stderr_and_import_exits_1(string engine)
    {
        var store = Store(engine);
        var source = Path.Combine(_folder.Path, "bad.nc");
        File.WriteAllText(source, $"({Guid.NewGuid():N})\nG1 X1 Q#\nM30\n");
        var (code, stdout, stderr) = Run("programs", "import", source, "--store", store);
        code.Should().Be(1);
        stdout.Trim().Should().MatchRegex("^[0-9]+$", "the revision is stored, and only its id is printed");
        stderr.Should().MatchRegex(@"bad\.nc:2:\d+: error E\d+: ", "diagnostics as FILE:LINE:COL: error CODE: message");
        var show = Run("programs", "show", stdout.Trim(), "--json", "--store", store);
        using var doc = JsonDocument.Parse(show.Out);
        doc.RootElement.GetProperty("errors").GetInt32().Should().BeGreaterThan(0);
        doc.RootElement.GetProperty("diagnostics").GetArrayLength().Should().BeGreaterThan(0);
    }

    [Fact]
    public void A_password_never_appears_in_a_message()
    {
        var (code, _, stderr) = Run("programs", "list", "--store", "postgres://station:s3cret-pw@127.0.0.1:1/nowhere");
        code.Should().NotBe(0);
        stderr.Should().NotContain("s3cret-pw").And.Contain("postgres://station@127.0.0.1:1/nowhere");
    }

    [Fact]
    public void A_stored_revision_runs_under_the_profile_it_was_imported_with()
    {
        var store = Store("sqlite");
        var source = Path.Combine(_folder.Path, "owords.ngc");
        File.WriteAllText(source, "G21 G90 G17\n#1 = 0\no100 while [#1 LT 3]\nG01 X[#1] Y1 F600\n#1 = [#1 + 1]\no100 endwhile\nM2\n", new UTF8Encoding(false));
        Run("programs", "import", source, "--store", store).Code.Should().Be(1, "o-words are not FANUC: refused under the default profile");

        var (code, stdout, stderr) = Run("programs", "import", source, "--profile", "linuxcnc-mill", "--store", store);
        code.Should().Be(0, stderr);
        var id = stdout.Trim();
        var run = Run("stream", "--program", id, "--sim", "--sim-speed", "instant", "--stops", "continue", "--store", store);
        run.Code.Should().Be(0, "no --profile: the revision's own (linuxcnc-mill); " + run.Out + run.Err);
        System.Text.RegularExpressions.Regex.Match(run.Out, @"executed (\d+) of \1 blocks").Success.Should().BeTrue(run.Out);
        Run("stream", "--program", id, "--profile", "fanuc-mill", "--sim", "--sim-speed", "instant", "--stops", "continue", "--store", store)
            .Code.Should().NotBe(0, "--profile still says which profile the gate checks under");
    }

    private string Store(string engine)
    {
        if (engine == "sqlite")
        {
            return "sqlite:" + Path.Combine(_folder.Path, "store.db");
        }

        var (station, admin) = Requires.Postgres();
        if (admin is not null)
        {
            using (PgSchema.OpenMigrated(StoreLocation.Parse(admin)))
            {
            }
        }

        return station;
    }

    /// <summary>
    /// Runs the command line: <c>stream</c> as a process with this test's own home (the program cache lives there, and
    /// the home is the process's), the store's own commands (every one given <c>--store</c>) in process.
    /// </summary>
    private (int Code, string Out, string Err) Run(params string[] args) => args[0] == "stream" ? RunWithHome(args) : CliRun.InProcess(args);

    private (int Code, string Out, string Err) RunWithHome(string[] args)
    {
        var psi = CliProcess.Info(args);
        psi.Environment["HOME"] = _folder.Path;
        psi.Environment.Remove("PMACSTREAM_STORE");
        using var p = Process.Start(psi)!;
        p.StandardInput.Close();
        var stdout = p.StandardOutput.ReadToEndAsync();
        var stderr = p.StandardError.ReadToEndAsync();
        if (!p.WaitForExit(120_000))
        {
            p.Kill(true);
            throw new TimeoutException($"pmacstream {string.Join(' ', args)} did not finish");
        }

        return (p.ExitCode, stdout.Result, stderr.Result);
    }
}
