using System.Diagnostics;
using System.Globalization;
using System.Text.Json;
using PmacStream.IntegrationTests.Transports;
using PmacStream.Pmac;

namespace PmacStream.IntegrationTests.Console;

/// <summary>
/// The console commands run as the operator runs them, against one `pmacstream sim` process over TCP, with a job
/// store, alarm history, state file and tables file of their own. They run in the test's process
/// (<see cref="CliRun"/>) with <c>--settings</c> naming the test's settings file, so the tables file is the one beside
/// it; <c>resume</c> runs as a process with the environment pointing the tables and settings into the test's folder,
/// because a resume given <c>--settings</c> takes that file's settings instead of the job's recorded ones.
/// </summary>
internal sealed class ConsoleCli
{
    public ConsoleCli(SimProcess sim, string folder)
    {
        Sim = sim;
        Folder = folder;
        if (!File.Exists(SettingsFile))
        {
            File.WriteAllText(SettingsFile, "{}"); // the defaults, as when the file is absent
        }
    }

    public string Folder { get; }

    public SimProcess Sim { get; }

    public string[] Target => ["--tcp", "127.0.0.1:" + Sim.Port.ToString(CultureInfo.InvariantCulture), "--job-db", Path.Combine(Folder, "jobs.db")];

    private string SettingsFile => Path.Combine(Folder, "settings.json");

    /// <summary>Runs `pmacstream ARGS --tcp ... --job-db ...` and returns its exit code and output.</summary>
    public (int Code, string Out, string Err) Run(params string[] args) =>
        args[0] == "resume" ? RunProcess(args) : CliRun.InProcess([.. args, .. Target, "--settings", SettingsFile]);

    private (int Code, string Out, string Err) RunProcess(string[] args)
    {
        var psi = new ProcessStartInfo("dotnet") { RedirectStandardOutput = true, RedirectStandardError = true, RedirectStandardInput = true, UseShellExecute = false };
        psi.ArgumentList.Add(Path.Combine(AppContext.BaseDirectory, "pmacstream.dll"));
        foreach (var a in args.Concat(Target))
        {
            psi.ArgumentList.Add(a);
        }

        psi.Environment["PMACSTREAM_TABLES"] = Path.Combine(Folder, "tables.json");
        psi.Environment["PMACSTREAM_SETTINGS"] = SettingsFile;
        using var p = Process.Start(psi)!;
        p.StandardInput.Close();
        var stdout = p.StandardOutput.ReadToEndAsync();
        var stderr = p.StandardError.ReadToEndAsync();
        if (!p.WaitForExit(180_000))
        {
            p.Kill(true);
            throw new TimeoutException($"pmacstream {string.Join(' ', args)} did not finish");
        }

        return (p.ExitCode, stdout.Result, stderr.Result);
    }

    /// <summary>Runs a command that must succeed.</summary>
    public string Ok(params string[] args)
    {
        var (code, stdout, stderr) = Run(args);
        code.Should().Be(0, $"pmacstream {string.Join(' ', args)} must succeed; stdout: {stdout}; stderr: {stderr}");
        return stdout;
    }

    /// <summary>`status --json`, parsed.</summary>
    public JsonElement Status()
    {
        var line = Ok("status", "--json").Trim();
        line.Split('\n').Should().ContainSingle("one sample without --watch");
        using var doc = JsonDocument.Parse(line);
        return doc.RootElement.Clone();
    }

    /// <summary>The motor positions (counts = mm at the simulator's scale 1) read straight from the simulator.</summary>
    public async Task<double[]> MotorPositionsAsync()
    {
        await using var eth = new EthernetConnection(new EthernetOptions { Port = Sim.Port, Timeout = TimeSpan.FromSeconds(5) });
        var reply = await eth.GetResponseAsync("#1P#2P#3P");
        return reply.Split(['\r', '\n', ' '], StringSplitOptions.RemoveEmptyEntries).Select(v => double.Parse(v, CultureInfo.InvariantCulture)).ToArray();
    }

    /// <summary>An axis of a `status --json` sample.</summary>
    public static JsonElement Axis(JsonElement status, string name) =>
        status.GetProperty("axes").EnumerateArray().Single(a => a.GetProperty("name").GetString() == name);

    /// <summary>
    /// The executed-move log's block starts (source lines) once the simulator stopped (SIGTERM writes the log).
    /// </summary>
    public static List<int> BlockStarts(string log) =>
        File.ReadLines(log).Skip(1).Select(l => l.Split(','))
            .Where(f => f[^1] == "1" && int.Parse(f[1], CultureInfo.InvariantCulture) > 0)
            .Select(f => int.Parse(f[1], CultureInfo.InvariantCulture)).ToList();
}
