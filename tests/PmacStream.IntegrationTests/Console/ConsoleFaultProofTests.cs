using System.Globalization;
using System.Text.Json;
using PmacStream.IntegrationTests.Transports;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Console;

/// <summary>
/// The fault proof (issue 25): each fault kind, injected into `pmacstream sim` at a random time of a 20,000-block job,
/// holds the job with an exact checkpoint; the alarm shows in `status --json` and `alarms --json`; after
/// `alarms clear` (and a jog off the limit) `resume` ends the job with every block executed once, in order, by the
/// simulator's executed-move log. One job per kind here, the strategies spread over them (chunk, pr, adaptive) to stay
/// in the test budget; `bench/console-faults.sh` runs every kind under every strategy.
/// </summary>
public sealed class ConsoleFaultProofTests(ITestOutputHelper output) : IDisposable
{
    private const int Moves = 20_000;
    private readonly TestFolder _temp = new("console-fault");

    public void Dispose() => _temp.Dispose();

    [Theory]
    [InlineData("limit+", 1, "chunk")]
    [InlineData("limit-", 2, "pr")]
    [InlineData("fatal-following-error", 3, "adaptive")]
    [InlineData("amp-fault", 1, "chunk")]
    public void A_fault_during_a_job_holds_it_and_after_clear_and_resume_every_block_ran_once_in_order(string kind, int motor, string strategy)
    {
        // 20,000 moves of 10 ms: 200 s on the simulator's clock. The fault lands somewhere in its first 150 s.
        // PMACSTREAM_FAULT_SEED replays a failed run's fault time (the seed is in the test's output).
        var seed = int.TryParse(Environment.GetEnvironmentVariable("PMACSTREAM_FAULT_SEED"), CultureInfo.InvariantCulture, out var s) ? s : Environment.TickCount;
        var at = Math.Round(2 + (new Random(seed).NextDouble() * 148), 2);
        output.WriteLine(string.Create(CultureInfo.InvariantCulture, $"{kind} on motor {motor} at {at} s (seed {seed}), strategy {strategy}"));
        var program = RasterProgram.Write(Path.Combine(_temp.Path, "raster.nc"), Moves);
        var log = Path.Combine(_temp.Path, "executed.csv");
        using var sim = SimProcess.Start("--tcp", "0", "--speed", "20x", "--executed-log", log, "--inject", string.Create(CultureInfo.InvariantCulture, $"{kind}:{motor}@{at}"));
        var cli = new ConsoleCli(sim, _temp.Path);
        cli.Ok("home");

        var held = cli.Run("stream", program, "--strategy", strategy);
        held.Code.Should().Be(1, $"the alarm stops the job; stdout: {held.Out}; stderr: {held.Err}");
        held.Err.Should().Contain("alarm at line");
        var job = System.Text.RegularExpressions.Regex.Match(held.Out, @"job (\d+):").Groups[1].Value;
        output.WriteLine(held.Err.Trim());

        var status = cli.Status();
        status.GetProperty("state").GetString().Should().Be("alarm");
        HasAlarm(status.GetProperty("alarms"), kind, motor).Should().BeTrue($"status --json shows {kind} on motor {motor}: {status}");
        HasAlarm(JsonDocument.Parse(cli.Ok("alarms", "--json")).RootElement.GetProperty("alarms"), kind, motor).Should().BeTrue("alarms --json shows it");
        var early = cli.Run("resume", "--job", job, "--yes");
        early.Code.Should().Be(1, "no resume while the alarm is active");
        early.Err.Should().Contain("an alarm is active");

        cli.Ok("alarms", "clear");
        if (kind.StartsWith("limit", StringComparison.Ordinal))
        {
            var axis = "XYZ"[motor - 1].ToString();
            var into = cli.Run("jog", axis, kind == "limit+" ? "+0.5" : "-0.5");
            into.Code.Should().Be(1, "a jog further into the limit is refused");
            cli.Ok("jog", axis, kind == "limit+" ? "-1" : "+1"); // off the limit, away from it: always allowed
        }

        var cleared = cli.Status();
        cleared.GetProperty("alarms").EnumerateArray().Should().BeEmpty();
        cleared.GetProperty("state").GetString().Should().Be("held", "the job waits to be resumed");

        var resumed = cli.Run("resume", "--job", job, "--yes");
        resumed.Code.Should().Be(0, $"resume ends the job; stdout: {resumed.Out}; stderr: {resumed.Err}");
        output.WriteLine(resumed.Out.Split('\n').Last(l => l.StartsWith("executed", StringComparison.Ordinal)));
        var history = JsonDocument.Parse(cli.Ok("alarms", "--history", "--json")).RootElement.GetProperty("history");
        history.EnumerateArray().Should().Contain(h => h.GetProperty("code").GetString() == kind && h.GetProperty("cleared").ValueKind == JsonValueKind.String);
        sim.Terminate().Should().Be(0);

        var expected = File.ReadLines(program).Select((l, i) => (l, i + 1)).Where(x => x.l.StartsWith("G0", StringComparison.Ordinal)).Select(x => x.Item2).ToList();
        ConsoleCli.BlockStarts(log).Should().Equal(expected, "every block ran once, in order, across the alarm, the clear and the resume");
    }

    private static bool HasAlarm(JsonElement alarms, string code, int motor) =>
        alarms.EnumerateArray().Any(a => a.GetProperty("code").GetString() == code && a.GetProperty("motor").GetInt32() == motor && a.GetProperty("text").GetString()!.Length > 0);
}
