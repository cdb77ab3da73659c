using System.CommandLine;
using PmacStream.Jobs;
using PmacStream.Machine;

namespace PmacStream.Cli.Commands;

/// <summary>
/// The options every console command shares (the controller as <c>stream</c> takes it, the job store, the settings, the
/// profile, the tables file, the alarm language) and the console they open. The logic is in <see cref="MachineConsole"/>;
/// the commands only bind and print.
/// </summary>
internal sealed class ConsoleOptions
{
    private readonly Option<string?> _tables = new("--tables") { Description = "The host's copy of the work offsets and tool table (JSON); default $PMACSTREAM_TABLES or tables.json beside the settings file." };
    private readonly Option<string?> _language = new("--lang") { Description = "Language of alarm texts: en (the default) or zh-CN.", HelpName = "en|zh-CN" };
    private readonly Option<string?> _profile = CliProfiles.Option();
    private JobOptions _job = null!;

    /// <summary>Adds the options to <paramref name="cmd"/>.</summary>
    public static ConsoleOptions AddTo(Command cmd)
    {
        var o = new ConsoleOptions();
        o._job = JobOptions.AddTo(cmd, JobFace.Console);
        cmd.Options.Add(o._tables);
        cmd.Options.Add(o._language);
        cmd.Options.Add(o._profile);
        return o;
    }

    /// <summary>These options as one command line gives them, for its handler.</summary>
    public ConsoleArgs Bind(ParseResult parse) => new(this, parse);

    /// <summary>The tables file.</summary>
    public string TablesPath(ParseResult parse) => parse.GetValue(_tables) ?? MachineTables.DefaultPath(_job.SettingsPath(parse));

    /// <summary>Opens the controller and the console on it; a command that moves the machine (<paramref name="lease"/>) leases it first.</summary>
    public async Task<ConsoleSession> OpenAsync(ParseResult parse, CancellationToken cancellationToken, bool lease = false)
    {
        var target = _job.Target(parse) ?? throw new CliException("say which controller: --sim, --tcp HOST[:PORT] or --serial DEV[,BAUD]");
        var held = lease ? _job.Lease(parse, target) : null; // before the controller hears anything
        var language = parse.GetValue(_language) ?? "en";
        if (language is not ("en" or "zh-CN" or "zh"))
        {
            throw new CliException($"--lang {language}: expected en or zh-CN");
        }

        var tablesPath = TablesPath(parse);
        var profile = ToolTableProfile.Apply(CliProfiles.Load(parse.GetValue(_profile)), MachineTables.Load(tablesPath));
        var settings = _job.Settings(parse);
        var sim = new CliSimulator(_job.SimSpeed(parse), profile.RapidRate);
        var service = new JobService(new JobServiceOptions
        {
            Store = _job.Store(parse), Simulator = sim.OpenAsync, Rules = new MachineRules(MachineAxis.Of(profile)),
        });
        try
        {
            var controller = await service.ConnectAsync(target, profile, cancellationToken).ConfigureAwait(false);
            var console = new MachineConsole(service, controller, new MachineConsoleOptions
            {
                Language = language, TablesPath = tablesPath,
                History = StoreAlarmHistory.Of(service, controller.Spec.ToString()),
                StatePath = Path.Combine(MachineConsoleOptions.StateFolder(service), "console-state.json"), Profile = profile, Settings = settings,
                Axes = MachineAxis.Of(profile), CoordinateSystem = profile.CoordinateSystem,
            });
            if (controller.IsSimulator && File.Exists(tablesPath))
            {
                // The built-in simulator is a new controller each time: it starts with the host's copy of the tables.
                await console.RestoreTablesAsync(cancellationToken).ConfigureAwait(false);
            }

            return new ConsoleSession(sim, controller, console) { Lease = held };
        }
        catch
        {
            sim.Dispose();
            if (held is not null)
            {
                await held.DisposeAsync().ConfigureAwait(false);
            }

            throw;
        }
    }

    /// <summary>Prints a result: done on stdout (exit 0), refused as an error with the reason (exit 1).</summary>
    public static int Finish(ConsoleResult result) => Finish(result, CliConsole.Standard);

    /// <summary>Prints a result on <paramref name="console"/>: done on its output (exit 0), refused as an error with the reason (exit 1).</summary>
    public static int Finish(ConsoleResult result, CliConsole console)
    {
        if (!result.Done)
        {
            throw new CliException("refused: " + result.Message, CliGlobals.Failed);
        }

        console.Out.WriteLine(result.Message);
        return CliGlobals.Ok;
    }

    /// <summary>A number option's text as an invariant double, or a usage error naming it.</summary>
    public static double Number(string text, string what) =>
        double.TryParse(text, System.Globalization.NumberStyles.Float, System.Globalization.CultureInfo.InvariantCulture, out var v) && double.IsFinite(v)
            ? v
            : throw new CliException($"{what}: '{text}' is not a number");
}

/// <summary>An open console: the controller (and the built-in simulator when asked for), closed together.</summary>
internal sealed class ConsoleSession(CliSimulator sim, ControllerLink controller, MachineConsole console) : IAsyncDisposable
{
    /// <summary>The console.</summary>
    public MachineConsole Console { get; } = console;

    /// <summary>The machine's lease this command holds (home, jog, mdi), or null.</summary>
    public MachineLease? Lease { get; init; }

    /// <inheritdoc />
    public async ValueTask DisposeAsync()
    {
        await controller.DisposeAsync().ConfigureAwait(false);
        sim.Dispose();
        if (Lease is not null)
        {
            await Lease.DisposeAsync().ConfigureAwait(false);
        }
    }
}

/// <summary>The console options of one command line, bound: the handler opens the console with them.</summary>
internal sealed class ConsoleArgs(ConsoleOptions options, ParseResult parse)
{
    /// <inheritdoc cref="ConsoleOptions.OpenAsync"/>
    public Task<ConsoleSession> OpenAsync(CancellationToken cancellationToken, bool lease = false) => options.OpenAsync(parse, cancellationToken, lease);
}
