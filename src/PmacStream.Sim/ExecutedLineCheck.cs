namespace PmacStream.Sim;

/// <summary>
/// Checks, as moves finish, that the controller ran every block of a program once and in order, without keeping the
/// moves: the executed source lines are folded (one block may make several moves; line 0 is a preamble move, before
/// any tracking assignment) and compared one by one with the program's tracked lines, which are read lazily too.
/// </summary>
public sealed class ExecutedLineCheck
{
    private readonly IEnumerator<int> _expected;
    private readonly int? _fromLine;
    private readonly object _lock = new();
    private int _last;
    private long _expectedSeen;
    private bool _expectedDone;
    private PmacSimulator? _attached;

    /// <summary>
    /// A check against <paramref name="expected"/> (the tracked lines in program order); with <paramref name="fromLine"/>,
    /// executed lines before it are left out (a start from a line runs its preamble's moves first).
    /// </summary>
    public ExecutedLineCheck(IEnumerable<int> expected, int? fromLine = null)
    {
        ArgumentNullException.ThrowIfNull(expected);
        _expected = expected.GetEnumerator();
        _fromLine = fromLine;
    }

    /// <summary>Blocks executed (folded lines counted).</summary>
    public long Executed { get; private set; }

    /// <summary>The first place execution left the program's order, or null while it has not.</summary>
    public string? FirstBreak { get; private set; }

    /// <summary>The source lines of executed moves in execution order, one per block: repeats of a line folded, line 0 left out.</summary>
    public static IEnumerable<int> Fold(IEnumerable<int> sourceLines)
    {
        ArgumentNullException.ThrowIfNull(sourceLines);
        var last = 0;
        foreach (var line in sourceLines)
        {
            if (line > 0 && line != last)
            {
                last = line;
                yield return line;
            }
        }
    }

    /// <summary>Counts every move <paramref name="simulator"/> finishes from now on, until <see cref="Finish"/>.</summary>
    public ExecutedLineCheck Attach(PmacSimulator simulator)
    {
        ArgumentNullException.ThrowIfNull(simulator);
        lock (_lock)
        {
            _attached = simulator;
            simulator.MoveExecuted += Add;
        }

        return this;
    }

    /// <summary>Takes one finished move.</summary>
    public void Add(ExecutedMove move) => Add(move.SourceLine);

    /// <summary>Takes the source line of one finished move.</summary>
    public void Add(int sourceLine)
    {
        lock (_lock)
        {
            if (sourceLine <= 0 || sourceLine == _last)
            {
                return;
            }

            _last = sourceLine;
            if (_fromLine is { } from && sourceLine < from)
            {
                return;
            }

            Executed++;
            if (NextExpected() is { } want)
            {
                if (FirstBreak is null && want != sourceLine)
                {
                    FirstBreak = $"block order broken at block {Executed}: expected line {want}, executed line {sourceLine}";
                }
            }
            else
            {
                FirstBreak ??= $"block {Executed} (line {sourceLine}) executed after the program's last block";
            }
        }
    }

    /// <summary>Stops counting and reads the rest of the program: how many blocks it has, how many ran, in order or not.</summary>
    public ExecutedLineResult Finish()
    {
        lock (_lock)
        {
            if (_attached is { } sim)
            {
                sim.MoveExecuted -= Add;
                _attached = null;
            }

            while (NextExpected() is not null)
            {
            }

            return new ExecutedLineResult(Executed, _expectedSeen, FirstBreak);
        }
    }

    private int? NextExpected()
    {
        if (_expectedDone)
        {
            return null;
        }

        if (_expected.MoveNext())
        {
            _expectedSeen++;
            return _expected.Current;
        }

        _expectedDone = true;
        _expected.Dispose();
        return null;
    }
}

/// <summary>What an <see cref="ExecutedLineCheck"/> found.</summary>
/// <param name="Executed">Blocks executed.</param>
/// <param name="Expected">Blocks the program has (from the start line on).</param>
/// <param name="FirstBreak">The first place execution left the program's order, or null.</param>
public readonly record struct ExecutedLineResult(long Executed, long Expected, string? FirstBreak)
{
    /// <summary>Every block once, in order.</summary>
    public bool Exact => FirstBreak is null && Executed == Expected;
}
