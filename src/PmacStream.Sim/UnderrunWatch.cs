namespace PmacStream.Sim;

/// <summary>What running out of rotary lines means.</summary>
internal enum Starvation
{
    /// <summary>Nothing to count (not moved yet since the start, or already counted).</summary>
    None,

    /// <summary>An underrun: the buffer is open, so more lines were coming.</summary>
    Underrun,

    /// <summary>The end of the program (<see cref="RotaryEndBehaviour.EndWhenClosed"/> and the buffer closed).</summary>
    End,
}

/// <summary>
/// Tells a rotary underrun from the end of a rotary program. A running program that has moved since its start and
/// runs out of rotary lines with no motion left has starved: with the buffer open that is an underrun at once; with
/// it closed it looks like the end (or is the end, with <see cref="RotaryEndBehaviour.EndWhenClosed"/>), and it is
/// an underrun only if lines arrive later and a move starts again.
/// </summary>
internal sealed class UnderrunWatch
{
    private bool _moved;
    private bool _starved;
    private bool _starvedWhileClosed;

    /// <summary>The program starts (<c>R</c>, <c>S</c>): nothing has moved yet.</summary>
    public void Started()
    {
        _moved = false;
        Stopped();
    }

    /// <summary>The program stopped: no starved spell is open.</summary>
    public void Stopped()
    {
        _starved = false;
        _starvedWhileClosed = false;
    }

    /// <summary>The program waits for rotary lines with no motion left; <paramref name="bufferOpen"/> while the host may still send.</summary>
    public Starvation OutOfLines(bool bufferOpen, RotaryEndBehaviour endBehaviour)
    {
        if (_starved || !_moved)
        {
            return Starvation.None;
        }

        _starved = true;
        if (bufferOpen)
        {
            return Starvation.Underrun;
        }

        if (endBehaviour == RotaryEndBehaviour.EndWhenClosed)
        {
            return Starvation.End;
        }

        _starvedWhileClosed = true;
        return Starvation.None;
    }

    /// <summary>A move starts; true when it ends a starved spell that looked like the end: an underrun after all.</summary>
    public bool MoveStarted()
    {
        var late = _starved && _starvedWhileClosed;
        Stopped();
        _moved = true;
        return late;
    }
}
