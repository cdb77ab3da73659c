using PmacStream.Hmi;
using PmacStream.Pmac;
using PmacStream.Sim;
using Serilog;

namespace PmacStream.WinForms;

/// <summary>Entry point of the HMI: composes the form, the presenter and the core, as in the paper's Fig. 4.</summary>
internal static class Program
{
    [STAThread]
    private static void Main()
    {
        ApplicationConfiguration.Initialize();

        // Everything the core logs at Information and above appears in the form's log pane.
        var sink = new HmiLogSink();
        Log.Logger = new LoggerConfiguration().MinimumLevel.Information().WriteTo.Hmi(sink).CreateLogger();

        // The built-in simulated Turbo PMAC: created on first connect, its clock in real time, reached through an
        // in-process port, with the PROG 1000/1001 G/M-code library downloaded as a real controller would need.
        PmacSimulator? simulator = null;
        var backend = new CoreHmiBackend(simulator: async cancellationToken =>
        {
            if (simulator is null)
            {
                simulator = new PmacSimulator(new SimOptions { Speed = SimSpeed.Realtime });
                simulator.StartClock();
            }

            var connection = new InProcessConnection(simulator.OpenPort("hmi"), "simulator (in-process)");
            await ControllerSetup.DownloadTolerantAsync(connection, ControllerSetup.Library(), cancellationToken);
            return connection;
        });

        using (var form = new MainForm())
        {
            var presenter = new MainPresenter(form, backend, sink);
            form.Attach(presenter);
            Application.Run(form);

            // The message loop has ended: release the job, the connection and the line index off the UI thread,
            // without waiting forever for work that would have needed the loop.
            try
            {
                Task.Run(() => presenter.DisposeAsync().AsTask()).Wait(TimeSpan.FromSeconds(3));
            }
            catch (AggregateException e)
            {
                Log.Warning(e.GetBaseException(), "Closing the HMI did not finish cleanly");
            }
        }

        simulator?.Dispose();
        Log.CloseAndFlush();
    }
}
