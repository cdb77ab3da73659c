using System.Diagnostics;
using Serilog;

namespace PmacStream.Sim;

/// <summary>
/// The background thread that moves the simulator's virtual time on with real time. Each round it measures the real
/// time since the last one (at most 0.25 s, so a stalled thread does not make time jump), runs one step under the
/// simulator's lock, lets the simulator deliver its events outside it, and, when the step says nothing is busy,
/// sleeps until woken or 1 ms has passed.
/// </summary>
/// <param name="sync">The simulator's lock.</param>
/// <param name="step">One step under the lock, given the real seconds since the last: true while busy (instant speed with motion to run).</param>
/// <param name="afterStep">Runs outside the lock after each step (event delivery).</param>
/// <param name="fault">Counts an unexpected exception of a step (a simulator bug), under the lock.</param>
internal sealed class SimClock(object sync, Func<double, bool> step, Action afterStep, Action<Exception> fault) : IDisposable
{
    private static readonly ILogger Log = Serilog.Log.ForContext<PmacSimulator>();

    private readonly AutoResetEvent _wake = new(false);
    private Thread? _thread;
    private volatile bool _stop;
    private bool _disposed;

    /// <summary>True while the thread runs.</summary>
    public bool Running => _thread is not null;

    /// <summary>Starts the thread (no-op when it runs). Call under the simulator's lock.</summary>
    public void Start()
    {
        ObjectDisposedException.ThrowIf(_disposed, this);
        if (_thread is not null)
        {
            return;
        }

        _stop = false;
        _thread = new Thread(Loop) { IsBackground = true, Name = "pmac-sim-clock" };
        _thread.Start();
    }

    /// <summary>Stops the thread and waits for it. Call outside the simulator's lock.</summary>
    public void Stop()
    {
        Thread? t;
        lock (sync)
        {
            t = _thread;
            _thread = null;
            _stop = true;
        }

        _wake.Set();
        t?.Join();
    }

    /// <summary>Wakes a sleeping thread (new lines arrived, motion may run); nothing when none runs.</summary>
    public void Wake()
    {
        if (_disposed || _thread is null)
        {
            return; // nobody waits; after Dispose the event is gone
        }

        try
        {
            _wake.Set();
        }
        catch (ObjectDisposedException)
        {
            // disposed concurrently: nothing to wake
        }
    }

    /// <inheritdoc />
    public void Dispose()
    {
        if (_disposed)
        {
            return;
        }

        Stop();
        _disposed = true;
        lock (sync)
        {
            _wake.Dispose();
        }
    }

    private void Loop()
    {
        // An exception on this thread would take the whole host process down (a server, a test run), so a fault
        // is logged and counted like a command fault, and the clock goes on.
        while (!_stop)
        {
            try
            {
                Run();
            }
            catch (Exception e)
            {
                lock (sync)
                {
                    fault(e);
                }

                Log.Error(e, "simulator clock fault");
                Thread.Sleep(1);
            }
        }
    }

    private void Run()
    {
        var sw = Stopwatch.StartNew();
        var last = sw.Elapsed.TotalSeconds;
        while (!_stop)
        {
            var nowReal = sw.Elapsed.TotalSeconds;
            var realDt = Math.Min(nowReal - last, 0.25);
            last = nowReal;
            bool busy;
            lock (sync)
            {
                if (_stop)
                {
                    break;
                }

                busy = step(realDt);
            }

            afterStep();
            if (!busy)
            {
                _wake.WaitOne(1);
            }
        }
    }
}
