namespace PmacStream.IntegrationTests.Plc;

/// <summary>The generated programs run in the independent evaluator (the simulator tests are in PlcSimulatorTests).</summary>
public class PlcBehaviourTests
{
    [Fact]
    public void Motor_program_behaves_like_the_relay_circuit_for_every_sequence_of_six_presses_evaluator()
    {
        var (program, generated) = PlcSamples.Load("motor-fwd-rev.ladder");
        var explorer = new MotorCircuitExplorer(new EvaluatorRig(program, generated), 6);
        explorer.Run();
        explorer.Steps.Should().Be(Enumerable.Range(1, 6).Sum(d => (long)Math.Pow(8, d)));
        explorer.Starts.Should().BePositive();
        explorer.SealIns.Should().BePositive();
        explorer.Stops.Should().BePositive();
        explorer.Trips.Should().BePositive();
        explorer.ReversalsAfterStop.Should().BePositive();
        explorer.RefusedReversals.Should().BePositive();
    }

    [Fact]
    public void A_wrong_rung_is_caught_by_the_exhaustive_check()
    {
        // Drop the interlock from KM2: the explorer must find a sequence where both contactors pull in.
        var text = File.ReadAllText(PlcSamples.Path_("motor-fwd-rev.ladder")).Replace("& !KM1 & !KR", "& !KR", StringComparison.Ordinal);
        var program = PmacStream.Plc.LadderParser.Parse(text);
        var rig = new EvaluatorRig(program, PmacStream.Plc.PlcGenerator.Generate(program));
        var act = () => new MotorCircuitExplorer(rig, 6).Run();
        act.Should().Throw<Xunit.Sdk.XunitException>().WithMessage("*gave outputs 3 after*press SB3");
    }
}

/// <summary>The sand-mould interlock sample in the evaluator rig.</summary>
public class SandMouldBehaviourTests
{
    internal static void ScenarioWalk(IPlcRig rig)
    {
        var c = new SandMouldChecker(rig);
        c.PowerUp(SandMould.Healthy);
        c.Outputs.Should().Be(SandMould.Ready, "a healthy machine at power-up is ready, nothing runs");
        c.Apply(SandMould.Healthy | SandMould.SpStart, "press spindle start");
        c.Outputs.Should().Be(SandMould.SpindleOut | SandMould.Dust);
        c.Apply(SandMould.Healthy, "release start");
        c.Outputs.Should().Be(SandMould.SpindleOut | SandMould.Dust, "the spindle seals in");
        c.Apply(SandMould.Healthy | SandMould.ClStart, "coolant on");
        c.Apply(SandMould.Healthy, "release coolant on");
        c.Outputs.Should().Be(SandMould.SpindleOut | SandMould.Dust | SandMould.CoolantOut);
        c.Apply(SandMould.EstopOk | SandMould.AirOk, "open the door");
        c.Outputs.Should().Be(SandMould.AlarmLamp, "door open stops everything and raises the alarm");
        c.Apply(SandMould.Healthy, "close the door");
        c.Outputs.Should().Be(SandMould.AlarmLamp, "the alarm stays latched");
        c.Apply(SandMould.Healthy | SandMould.SpStart, "press start during the alarm");
        c.Outputs.Should().Be(SandMould.AlarmLamp, "no start while the alarm is latched");
        c.Apply(SandMould.Healthy & ~SandMould.AirOk | SandMould.Reset, "reset without air");
        c.Outputs.Should().Be(SandMould.AlarmLamp, "reset does nothing while the chain is broken");
        c.Apply(SandMould.Healthy | SandMould.Reset, "air back, reset held");
        c.Outputs.Should().Be(SandMould.Ready);
        c.Apply(SandMould.Healthy, "release reset");
        c.Outputs.Should().Be(SandMould.Ready, "the spindle does not restart by itself");
        c.Apply(SandMould.Healthy | SandMould.SpStart | SandMould.SpStop, "start and stop together");
        c.Outputs.Should().Be(SandMould.Ready, "stop wins");
        c.Apply(SandMould.Healthy | SandMould.SpStart | SandMould.SpFault, "drive fault while starting");
        c.Outputs.Should().Be(SandMould.AlarmLamp);
    }

    internal static SandMouldChecker RandomWalks(IPlcRig rig, int walks, int length, int seed)
    {
        var rng = new Random(seed);
        var c = new SandMouldChecker(rig);
        for (var w = 0; w < walks; w++)
        {
            // Each walk starts from a power-up with a random input state (the images start cleared as after reset).
            rig.PowerUp();
            c.PowerUp(rng.Next(2) == 0 ? SandMould.Healthy : rng.Next(1 << SandMould.InputCount));
            for (var s = 0; s < length; s++)
            {
                var bit = 1 << rng.Next(SandMould.InputCount);
                c.Toggle(bit, $"toggle input {System.Numerics.BitOperations.Log2((uint)bit)}");
            }
        }

        return c;
    }

    [Fact]
    public void Sand_mould_scenario_evaluator() => ScenarioWalk(Rig());

    [Fact]
    public void Sand_mould_random_walks_follow_the_rules_evaluator()
    {
        var c = RandomWalks(Rig(), 400, 40, 000_2026);
        c.Steps.Should().Be(400 * 41);
        c.SpindleStarts.Should().BePositive();
        c.CoolantStarts.Should().BePositive();
        c.AlarmsLatched.Should().BePositive();
        c.AlarmsCleared.Should().BePositive();
    }

    private static EvaluatorRig Rig()
    {
        var (program, generated) = PlcSamples.Load("sand-mould-spindle.ladder");
        return new EvaluatorRig(program, generated);
    }
}
