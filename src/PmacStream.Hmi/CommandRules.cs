namespace PmacStream.Hmi;

/// <summary>Which commands the screen offers in which situation.</summary>
internal static class CommandRules
{
    /// <summary>The commands for the screen's state.</summary>
    /// <param name="busy">An operation or a connection attempt is under way.</param>
    /// <param name="connected">A controller is connected.</param>
    /// <param name="open">A program is open.</param>
    /// <param name="split">The program is split.</param>
    /// <param name="running">A job runs (or is held).</param>
    /// <param name="held">The job is held.</param>
    /// <param name="stopped">The job waits at a program stop (Resume continues it; there is nothing to hold).</param>
    public static CommandStates For(bool busy, bool connected, bool open, bool split, bool running, bool held, bool stopped = false)
    {
        if (busy)
        {
            // Hold and abort must stay reachable while a slow command runs.
            return CommandStates.None with { Hold = running, Abort = running };
        }

        var ready = connected && split && !running;
        return new CommandStates(
            Connect: !connected,
            Disconnect: connected && !running,
            Open: !running,
            Check: open && !running,
            Split: open && !running,
            Execute: ready,
            Hold: running && !held && !stopped,
            Resume: running,
            Abort: running,
            StartFromLine: ready,
            ResumeInterrupted: connected && open && !running);
    }
}
