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
