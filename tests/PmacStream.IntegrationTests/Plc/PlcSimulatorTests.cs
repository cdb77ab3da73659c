namespace PmacStream.IntegrationTests.Plc;

/// <summary>The generated programs run in the simulated Turbo PMAC (the kit's <see cref="SimulatorRig"/>).</summary>
public class PlcSimulatorTests
{
    [Fact]
    public async Task Motor_program_in_the_simulator_behaves_like_the_relay_circuit_for_every_sequence_of_six_presses()
    {
        var (program, generated) = PlcSamples.Load("motor-fwd-rev.ladder");
        using var rig = await SimulatorRig.CreateAsync(program, generated);
        var explorer = new MotorCircuitExplorer(rig, 6);
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
    public async Task Motor_program_logic_reads_only_the_images_sampled_at_the_start_of_the_scan()
    {
        var (program, generated) = PlcSamples.Load("motor-fwd-rev.ladder");
        using var rig = await SimulatorRig.CreateAsync(program, generated);
        rig.SetInputs(RelayMotor.Sb2);
        rig.Outputs.Should().Be(0, "nothing changes between scans");
        rig.Scan();
        rig.Outputs.Should().Be(1);
        rig.Simulator.GetWord('Y', program.Inputs.ImageAddress).Should().Be(RelayMotor.Sb2, "the input image holds the sampled inputs");
        rig.Simulator.GetWord('Y', program.Outputs.ImageAddress).Should().Be(1, "the output image holds the coils");
        (await rig.Connection.GetResponseAsync("M900")).Trim().Should().Be("1");
    }

    [Fact]
    public async Task Disable_plc_freezes_the_outputs_and_enable_resumes_the_scan()
    {
        var (program, generated) = PlcSamples.Load("motor-fwd-rev.ladder");
        using var rig = await SimulatorRig.CreateAsync(program, generated);
        rig.SetInputs(RelayMotor.Sb2);
        rig.Scan();
        rig.SetInputs(0);
        rig.Scan();
        rig.Outputs.Should().Be(1, "forward sealed in");
        await rig.Connection.GetResponseAsync("DIS PLC 10");
        rig.SetInputs(RelayMotor.Sb1);
        rig.Scan();
        rig.Outputs.Should().Be(1, "a disabled PLC does not scan");
        await rig.Connection.GetResponseAsync("ENABLE PLC 10");
        rig.Scan();
        rig.Outputs.Should().Be(0, "stop is seen once the PLC runs again");
    }

    [Fact]
    public async Task Motor_program_runs_on_the_virtual_clock_scan_by_scan()
    {
        var (program, generated) = PlcSamples.Load("motor-fwd-rev.ladder");
        using var rig = await SimulatorRig.CreateAsync(program, generated);
        rig.SetInputs(RelayMotor.Sb3);
        rig.Simulator.Advance(TimeSpan.FromMilliseconds(20));
        rig.Outputs.Should().Be(2, "reverse pulls in on the clock's scans");
        rig.SetInputs(RelayMotor.Sb2);
        rig.Simulator.Advance(TimeSpan.FromMilliseconds(20));
        rig.Outputs.Should().Be(2, "forward is locked out while reverse runs");
        rig.SetInputs(RelayMotor.Kr);
        rig.Simulator.Advance(TimeSpan.FromMilliseconds(20));
        rig.Outputs.Should().Be(0, "thermal trip");
    }

    [Fact]
    public async Task Sand_mould_scenario_in_the_simulator()
    {
        var (program, generated) = PlcSamples.Load("sand-mould-spindle.ladder");
        using var rig = await SimulatorRig.CreateAsync(program, generated);
        SandMouldBehaviourTests.ScenarioWalk(rig);
    }

    [Fact]
    public async Task Sand_mould_random_walks_in_the_simulator_follow_the_rules()
    {
        var (program, generated) = PlcSamples.Load("sand-mould-spindle.ladder");
        using var rig = await SimulatorRig.CreateAsync(program, generated);
        var c = SandMouldBehaviourTests.RandomWalks(rig, 200, 40, 000_2026);
        c.Steps.Should().Be(200 * 41);
        c.SpindleStarts.Should().BePositive();
        c.CoolantStarts.Should().BePositive();
        c.AlarmsLatched.Should().BePositive();
        c.AlarmsCleared.Should().BePositive();
    }
}
