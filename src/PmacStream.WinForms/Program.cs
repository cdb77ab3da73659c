using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Machine;
using PmacStream.Pmac;
using PmacStream.Sim;
using Serilog;

namespace PmacStream.WinForms;

/// <summary>
/// Entry point of the HMI: composes the form, the presenter and the core.
/// Options: <c>--sim-speed realtime|Nx</c> (the built-in simulator's clock, realtime by default) and
/// <c>--store URI</c> (the program and job store, as the command line's <c>--store</c>; else <c>$PMACSTREAM_STORE</c>) and
/// <c>--ui-test DIR</c> (the automated UI test's snapshot and command folder).
/// </summary>
internal static class Program
{
    [STAThread]
    private static int Main(string[] args)
    {
        if (ParseArguments(args) is not { } options)
        {
            return 2;
        }

        var (simSpeed, uiTestDirectory, store) = options;

        // What the WinForms SDK's generated ApplicationConfiguration.Initialize() does, written out so the project also
        // compiles against the runtime pack (no generator there).
        Application.SetHighDpiMode(HighDpiMode.SystemAware);
        Application.EnableVisualStyles();
        Application.SetCompatibleTextRenderingDefault(false);

        // Everything the core logs at Information and above appears in the form's log pane.
        var sink = new HmiLogSink();
        Log.Logger = new LoggerConfiguration().MinimumLevel.Information().WriteTo.Hmi(sink).CreateLogger();

        // The built-in simulated Turbo PMAC: created on first connect, its clock at --sim-speed (real time by default),
        // reached through an in-process port; the job service downloads the PROG 1000/1001 library as a real controller
        // would need.
        PmacSimulator? simulator = null;
        var service = new JobService(new JobServiceOptions
        {
            Simulator = _ =>
            {
                if (simulator is null)
                {
                    simulator = new PmacSimulator(new SimOptions { Speed = simSpeed, RapidFeed = PmacStream.GCode.MachineProfile.Default.RapidRate });
                    simulator.StartClock();
                }

                var connection = new InProcessConnection(simulator.OpenPort("hmi"), "simulator (in-process)");
                return Task.FromResult(new SimulatorLink(connection, new SimTimeProvider(simulator)));
            },

            // The store as the command line takes it: --store, else $PMACSTREAM_STORE, else ~/.pmacstream/store.db.
            StoreUri = store,

            // The operator's console rules: a job refuses to start unhomed or with an alarm, and an alarm holds it.
            Rules = new MachineRules(MachineAxis.Default),
        });

        var settings = LoadSettings();
        using (var form = new MainForm())
        {
            var backend = NewBackend(service, form.Language, settings);
            var presenter = new MainPresenter(form, backend, sink, settings: settings);
            form.Attach(presenter);
            var console = new ConsolePresenter(form, backend, backend, () => presenter.Profile);
            form.Attach(console);
            form.Attach(new StorePresenter(form, backend, presenter.OpenStoredAsync)
            {
                OpenRevision = (id, path, profile) => presenter.OpenStoredAsync(id, path, profile), Language = () => form.Language,
            });
            form.InjectFault = (kind, motor) => simulator?.InjectFault(FaultInjection.Parse($"{kind}:{motor}@0").Kind, motor);
            using var uiTest = uiTestDirectory is null ? null : new UiTestChannel(form, uiTestDirectory);
            Application.Run(form);

            // The message loop has ended: release the job, the connection and the line index off the UI thread,
            // without waiting forever for work that would have needed the loop.
            try
            {
                Task.Run(async () =>
                {
                    await console.DisposeAsync().ConfigureAwait(false);
                    await presenter.DisposeAsync().ConfigureAwait(false);
                }).Wait(TimeSpan.FromSeconds(3));
            }
            catch (AggregateException e)
            {
                Log.Warning(e.GetBaseException(), "Closing the HMI did not finish cleanly");
            }
        }

        simulator?.Dispose();
        Log.CloseAndFlush();
        return 0;
    }

    /// <summary>The job service's adapter with the console on the command line's files: one alarm history, one host copy of the tables, one MDI modal state.</summary>
    private static CoreHmiBackend NewBackend(JobService service, HmiLanguage language, RunSettings settings) => new(service)
    {
        ConsoleOptions = new MachineConsoleOptions
        {
            // The store's alarm history, for the controller the operator connects to (CoreHmiBackend names it).
            History = StoreAlarmHistory.Of(service, "sim"),
            TablesPath = MachineTables.DefaultPath(),
            StatePath = Path.Combine(MachineConsoleOptions.StateFolder(service), "console-state.json"),
            Language = language == HmiLanguage.Chinese ? "zh-CN" : "en",
            Settings = settings,
        },
    };

    /// <summary>The simulator's speed and the UI test folder from the command line; null (after saying why) when it is wrong.</summary>
    private static (SimSpeed SimSpeed, string? UiTestDirectory, string? Store)? ParseArguments(string[] args)
    {
        var simSpeed = SimSpeed.Realtime;
        string? uiTestDirectory = null;
        string? store = null;
        for (var i = 0; i < args.Length; i++)
        {
            var value = i + 1 < args.Length ? args[i + 1] : null;
            switch (args[i])
            {
                case "--sim-speed" when value is not null:
                    try
                    {
                        simSpeed = SimSpeed.Parse(value);
                    }
                    catch (Exception e) when (e is FormatException or ArgumentException)
                    {
                        Console.Error.WriteLine($"PmacStream.WinForms: --sim-speed {value}: {e.Message}");
                        return null;
                    }

                    i++;
                    break;
                case "--ui-test" when value is not null:
                    uiTestDirectory = value;
                    i++;
                    break;
                case "--store" when value is not null:
                    store = value;
                    i++;
                    break;
                default:
                    Console.Error.WriteLine($"PmacStream.WinForms: unknown option '{args[i]}' (use --sim-speed realtime|Nx, --store URI, --ui-test DIR)");
                    return null;
            }
        }

        return (simSpeed, uiTestDirectory, store);
    }

    /// <summary>The run settings the command line reads too (~/.pmacstream/settings.json when it exists).</summary>
    private static RunSettings LoadSettings()
    {
        try
        {
            return RunSettingsFile.Load();
        }
        catch (Exception e) when (e is RunSettingsException or IOException)
        {
            MessageBox.Show(e.Message, "PmacStream", MessageBoxButtons.OK, MessageBoxIcon.Warning);
            return RunSettings.Default;
        }
    }
}
