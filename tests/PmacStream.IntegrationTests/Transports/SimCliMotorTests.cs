using System.Globalization;
using PmacStream.Pmac;

namespace PmacStream.IntegrationTests.Transports;

/// <summary>`pmacstream sim` as a machine: unhomed unless --homed, and --inject faults landing after the program starts.</summary>
public sealed class SimCliMotorTests
{
    private static bool Bit(string status, int word, int bit) =>
        ((int.Parse(status.Substring((word - 1) * 6, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture) >> bit) & 1) == 1;

    private static EthernetConnection Connect(SimProcess sim) => new(new EthernetOptions { Port = sim.Port, Timeout = TimeSpan.FromSeconds(5) });

    [Fact]
    public async Task The_served_simulator_starts_unhomed_and_homed_with_the_option()
    {
        using (var sim = SimProcess.Start("--tcp", "0", "--speed", "instant", "--library", "none"))
        {
            await using (var eth = Connect(sim))
            {
                Bit(await eth.GetResponseAsync("#1?"), 2, 10).Should().BeFalse("incremental encoders: not homed at power-on");
                await eth.GetResponseAsync("I119=100 I121=1 #1HM");
                var homed = false;
                for (var i = 0; i < 100 && !homed; i++)
                {
                    homed = Bit(await eth.GetResponseAsync("#1?"), 2, 10) && Bit(await eth.GetResponseAsync("#1?"), 2, 0);
                    await Task.Delay(20);
                }

                homed.Should().BeTrue("HM sets Home Complete");
                (await eth.GetResponseAsync("#1P")).Should().Be("0");
            }

            sim.Terminate().Should().Be(0);
            sim.Output.Should().Contain("pmacstream sim: motors not homed at start (home with #nHM, or start with --homed)");
        }

        using (var sim = SimProcess.Start("--tcp", "0", "--speed", "instant", "--library", "none", "--homed"))
        {
            await using (var eth = Connect(sim))
            {
                Bit(await eth.GetResponseAsync("#1?"), 2, 10).Should().BeTrue("--homed");
            }

            sim.Terminate().Should().Be(0);
        }
    }

    [Fact]
    public async Task An_injected_limit_stops_the_program_at_its_time_after_the_program_started()
    {
        using var sim = SimProcess.Start("--tcp", "0", "--speed", "20x", "--library", "none", "--inject", "limit+:1@0.5", "--inject", "amp-fault:3@100");
        await using (var eth = Connect(sim))
        {
            await eth.GetResponseAsync("#1->1000X");
            await eth.GetResponseAsync("&1 OPEN PROG 1 CLEAR LINEAR ABS F600 X100 CLOSE");
            await eth.GetResponseAsync("&1 B1 R");
            var running = true;
            for (var i = 0; i < 200 && running; i++)
            {
                await Task.Delay(20);
                running = Bit(await eth.GetResponseAsync("&1??"), 1, 0);
            }

            running.Should().BeFalse("the limit aborted the program");
            var status = await eth.GetResponseAsync("#1?");
            Bit(status, 1, 21).Should().BeTrue("Positive End Limit Set");
            Bit(status, 2, 11).Should().BeTrue("Stopped on Position Limit");
            double.Parse(await eth.GetResponseAsync("#1P"), CultureInfo.InvariantCulture).Should().BeApproximately(5000, 1, "0.5 s at 10 mm/s, 1000 counts/mm");
        }

        sim.Terminate().Should().Be(0);
        sim.Output.Should().Contain("pmacstream sim: will inject limit+:1@0.5 (0.5 s after a motion program first starts)");
    }

    [Fact]
    public void A_bad_fault_is_refused_with_the_form_it_takes()
    {
        using var sim = SimProcess.Start("--tcp", "0", "--inject", "limit:1@2");
        sim.Terminate().Should().Be(2, "a usage error, as for every bad option");
        sim.Output.Should().Contain(l => l.Contains("--inject 'limit:1@2': KIND must be one of limit+, limit-, fatal-following-error, amp-fault", StringComparison.Ordinal));
    }
}
