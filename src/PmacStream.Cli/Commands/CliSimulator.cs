using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Cli.Commands;

/// <summary>
/// The built-in simulator of one command: made when the job service connects to <c>sim</c>, its virtual clock stepped
/// by the job's tick loop (deterministic; <c>instant</c> means as fast as sensible). Its executed moves are not kept:
/// the job's <see cref="ExecutedLineCheck"/> counts them as they finish, so memory does not grow with the program.
/// </summary>
/// <param name="speed">The virtual clock's speed.</param>
/// <param name="rapidRate">The machine's rapid rate (mm/min; the profile's, so the host's move times agree); the default profile's when null.</param>
internal sealed class CliSimulator(SimSpeed speed, double? rapidRate = null) : IDisposable
{
    /// <summary>The simulator once opened, else null.</summary>
    public PmacSimulator? Sim { get; private set; }

    /// <summary>Opens a new simulator (a fresh controller: it holds no earlier job).</summary>
    public Task<SimulatorLink> OpenAsync(CancellationToken cancellationToken)
    {
        Sim?.Dispose();
        // Homed at start: the command itself stands for an operator who homed the machine, so `demo` and every `--sim`
        // run work as they always have (a served `pmacstream sim` starts unhomed).
        var sim = Sim = new PmacSimulator(new SimOptions { Speed = speed, RetainExecutedMoves = false, StartHomed = true, RapidFeed = rapidRate ?? MachineProfile.Default.RapidRate });
        var connection = new InProcessConnection(sim.OpenPort("stream"), "sim");
        return Task.FromResult(new SimulatorLink(connection, new SimTimeProvider(sim))
        {
            Step = sim.Advance,
            ClockFactor = speed.IsInstant ? 1000 : speed.Multiplier,
            Fresh = true,
        });
    }

    /// <inheritdoc />
    public void Dispose() => Sim?.Dispose();
}
