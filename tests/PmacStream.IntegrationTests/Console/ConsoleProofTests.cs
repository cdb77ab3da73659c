using System.Globalization;
using System.Text.Json;
using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.IntegrationTests.Transports;
using Xunit.Abstractions;

namespace PmacStream.IntegrationTests.Console;

/// <summary>
/// The console's proofs (issue 25) with the commands as the issue writes them, each run through the `pmacstream` parser and handlers (<see cref="ConsoleCli"/>) against a
/// `pmacstream sim` process over TCP: the position proof (homing, jogs, MDI, a program in G55) and the G41 tool radius
/// read from the tool table.
/// </summary>
public sealed class ConsoleProofTests(ITestOutputHelper output) : IDisposable
{
    private readonly TestFolder _temp = new("console");

    public void Dispose() => _temp.Dispose();

    [Fact]
    public async Task Status_equals_the_motor_positions_after_homing_jogs_and_mdi_and_a_G55_program_lands_where_the_interpreter_says()
    {
        using var sim = SimProcess.Start("--tcp", "0", "--speed", "50x");
        var cli = new ConsoleCli(sim, _temp.Path);
        var first = cli.Status();
        first.GetProperty("homed").EnumerateObject().Should().OnlyContain(h => !h.Value.GetBoolean(), "pmacstream sim starts unhomed");
        var refused = cli.Run("mdi", "G0 X1");
        refused.Code.Should().Be(1);
        refused.Err.Should().Contain("not homed");

        cli.Ok("home", "all").Should().Contain("homed XYZ");
        cli.Status().GetProperty("homed").EnumerateObject().Should().OnlyContain(h => h.Value.GetBoolean());
        await SameAsMotors(cli, 0, 0, 0);

        cli.Ok("jog", "X", "+1.5");
        cli.Ok("jog", "X", "-0.25", "--feed", "600");
        for (var i = 0; i < 3; i++)
        {
            cli.Ok("jog", "Y", "+0.1");
        }

        cli.Ok("jog", "Z", "-1");
        await SameAsMotors(cli, 1.25, 0.3, -1);
        cli.Ok("mdi", "G0 X10 Y10");
        await SameAsMotors(cli, 10, 10, -1);
        cli.Ok("mdi", "G91", "G1 X2 F600");
        cli.Ok("mdi", "Y-1"); // G91 and G01 carry on from the last MDI, as on a control
        await SameAsMotors(cli, 12, 9, -1);

        cli.Ok("offsets", "set", "G55", "X100", "Y50", "Z-10").Should().Contain("G55 X100 Y50 Z-10");
        var offsets = JsonDocument.Parse(cli.Ok("offsets", "--json")).RootElement;
        offsets.GetProperty("offsets").EnumerateArray().Single(o => o.GetProperty("name").GetString() == "G55").GetProperty("y").GetDouble().Should().Be(50);
        cli.Ok("offsets", "set", "G55", "Z-20").Should().Contain("G55 X100 Y50 Z-20", "axes not named stay as they are");

        var program = Path.Combine(_temp.Path, "g55.nc");
        File.WriteAllText(program, "G21 G90 G55 G17\nG00 X5 Y6 Z7\nG01 X8 F600\nG02 X12 Y6 I2 J0\n"); // no M30: its reset would make G54 active again
        var interpreter = new Interpreter(MachineProfile.Default);
        foreach (var block in GCodeReader.ReadAll(program))
        {
            interpreter.Step(block);
        }

        var end = interpreter.Position;
        cli.Ok("stream", program, "--strategy", "chunk").Should().MatchRegex(@"executed (\d+) of \1 blocks");
        var status = cli.Status();
        status.GetProperty("workOffset").GetString().Should().Be("G55");
        foreach (var (axis, work, offset) in new[] { ("X", end.X, 100.0), ("Y", end.Y, 50.0), ("Z", end.Z, -20.0) })
        {
            ConsoleCli.Axis(status, axis).GetProperty("work").GetDouble().Should().BeApproximately(work, 0.001, $"{axis} in work coordinates is where the interpreter ends");
            ConsoleCli.Axis(status, axis).GetProperty("machine").GetDouble().Should().BeApproximately(work + offset, 0.001, $"{axis} in machine coordinates is the work position plus G55");
        }

        await SameAsMotors(cli, end.X + 100, end.Y + 50, end.Z - 20);

        // Touch-off: X reads 0 here in G54.
        cli.Ok("offsets", "set", "G54", "--touch", "X0");
        cli.Ok("mdi", "G90 G54 G0 Y0");
        ConsoleCli.Axis(cli.Status(), "X").GetProperty("work").GetDouble().Should().BeApproximately(0, 0.001);
        sim.Terminate().Should().Be(0);
    }

    [Fact]
    public void A_G41_program_refused_for_want_of_a_radius_runs_once_the_tool_table_has_it()
    {
        var log = Path.Combine(_temp.Path, "executed.csv");
        using var sim = SimProcess.Start("--tcp", "0", "--speed", "50x", "--homed", "--executed-log", log);
        var cli = new ConsoleCli(sim, _temp.Path);
        var program = Path.Combine(_temp.Path, "g41.nc");
        File.WriteAllText(program, "G21 G90 G54 G17\nG00 X0 Y-20 Z5\nG01 Z-1 F600\nG41 D1 X0 Y0\nY20\nX20\nY0\nG40 X40 Y-20\nG00 Z5\nM30\n");
        var refused = cli.Run("stream", program, "--strategy", "chunk");
        refused.Code.Should().Be(1);
        (refused.Out + refused.Err).Should().Contain("E132");

        cli.Ok("tools", "set", "1", "--length", "50.2", "--radius", "3").Should().Contain("T1 length 50.2 radius 3");
        var tools = JsonDocument.Parse(cli.Ok("tools", "--json")).RootElement.GetProperty("tools").EnumerateArray().Single(t => t.GetProperty("number").GetInt32() == 1);
        tools.GetProperty("radius").GetDouble().Should().Be(3);
        tools.GetProperty("length").GetDouble().Should().Be(50.2);
        cli.Ok("tools", "set", "1", "--radius-wear", "-0.1").Should().Contain("radius 3 length wear 0 radius wear -0.1", "values not given stay");
        cli.Run("tools", "set", "1", "--radius", "-2").Code.Should().Be(1, "a negative radius is out of range");

        var ran = cli.Ok("stream", program, "--strategy", "chunk");
        ran.Should().MatchRegex(@"executed (\d+) of \1 blocks");
        output.WriteLine(ran.Split('\n').Last(l => l.Length > 0));

        // The square runs clockwise with the cutter on the left, outside it, 2.9 mm (radius plus wear) from each side:
        // the first side (X0, Y0 to Y20) runs at X -2.9, the third (X20, down to Y0) at X 22.9.
        sim.Terminate().Should().Be(0);
        var ends = File.ReadLines(log).Skip(1).Select(l => l.Split(',')).Select(f => (X: double.Parse(f[4], CultureInfo.InvariantCulture), Y: double.Parse(f[5], CultureInfo.InvariantCulture))).ToList();
        ends.Should().Contain(e => Math.Abs(e.X + 2.9) < 0.001 && Math.Abs(e.Y - 20) < 0.001, "the compensated first side runs 2.9 mm left of the programmed one");
        ends.Should().Contain(e => Math.Abs(e.X - 22.9) < 0.001, "the compensated third side runs 2.9 mm outside X20");
    }

    [Fact]
    public void A_profile_with_absolute_encoders_runs_a_job_on_an_unhomed_machine()
    {
        using var sim = SimProcess.Start("--tcp", "0", "--speed", "50x");
        var cli = new ConsoleCli(sim, _temp.Path);
        var program = Path.Combine(_temp.Path, "absolute.nc");
        File.WriteAllText(program, "G21 G90 G54\nG01 X2 Y1 F600\n");
        cli.Run("stream", program, "--strategy", "chunk").Err.Should().Contain("not homed", "incremental encoders (the default profile) home first");

        var json = JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["name"] = "absolute-mill";
        json["absoluteEncoders"] = true;
        var profile = Path.Combine(_temp.Path, "absolute.json");
        File.WriteAllText(profile, json.ToJsonString());
        MachineProfile.Parse(File.ReadAllText(profile), profile).AbsoluteEncoders.Should().BeTrue();
        MachineProfile.Default.ToJson().Should().NotContain("absoluteEncoders", "written only when set: the built-in profiles' identity stays");

        cli.Ok("stream", program, "--profile", profile, "--load-library", "--strategy", "chunk").Should().MatchRegex(@"executed (\d+) of \1 blocks");
        cli.Status().GetProperty("homed").EnumerateObject().Should().OnlyContain(h => !h.Value.GetBoolean(), "the job ran without homing the machine");
    }

    private static async Task SameAsMotors(ConsoleCli cli, double x, double y, double z)
    {
        var status = cli.Status();
        var motors = await cli.MotorPositionsAsync();
        var expected = new[] { x, y, z };
        var names = new[] { "X", "Y", "Z" };
        for (var i = 0; i < 3; i++)
        {
            var machine = ConsoleCli.Axis(status, names[i]).GetProperty("machine").GetDouble();
            machine.Should().BeApproximately(motors[i], 0.001, $"status --json {names[i]} equals the simulator's motor {i + 1} position");
            machine.Should().BeApproximately(expected[i], 0.001, string.Create(CultureInfo.InvariantCulture, $"{names[i]} is where the commands put it"));
        }
    }
}
