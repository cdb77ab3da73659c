using PmacStream.Pmac;

namespace PmacStream.Sim;

/// <summary>
/// Checks, as moves finish, that the controller ran every block of a program once and in order, without keeping the
/// moves: the executed moves are counted as blocks (<see cref="BlockStarts"/>: where the line changes or the block's
/// synchronous tracking assignment fired again; a block's further moves are not counted; line 0 is a preamble move)
/// and compared one by one with the program's tracked lines, which are read lazily too. So a one-move block run twice
/// in a row counts twice.
/// </summary>
public sealed class ExecutedLineCheck
{
    private readonly IEnumerator<int> _expected;
    private readonly int? _fromLine;
    private readonly object _lock = new();
    private readonly BlockStarts _starts;
    private long _expectedSeen;
    private bool _expectedDone;
    private PmacSimulator? _attached;

    /// <summary>
    /// A check against <paramref name="expected"/> (the tracked lines in program order); with <paramref name="fromLine"/>,
    /// executed lines before it are left out (a start from a line runs its preamble's moves first).
    /// <paramref name="expandedBlocks"/>: the blocks whose tracking assignment the program carries more than once (see <see cref="BlockStarts"/>).
    /// </summary>
    public ExecutedLineCheck(IEnumerable<int> expected, int? fromLine = null, IReadOnlyDictionary<int, int>? expandedBlocks = null)
    {
        ArgumentNullException.ThrowIfNull(expected);
        _expected = expected.GetEnumerator();
        _fromLine = fromLine;
        _starts = new BlockStarts(expandedBlocks);
    }

    /// <summary>Blocks executed.</summary>
    public long Executed { get; private set; }

    /// <summary>The first place execution left the program's order, or null while it has not.</summary>
    public string? FirstBreak { get; private set; }

    /// <summary>
    /// The source line of each block the moves executed, in execution order (<see cref="BlockStarts"/>, with the
    /// program's <paramref name="expandedBlocks"/>); line 0 is left out.
    /// </summary>
    public static IEnumerable<int> Blocks(IEnumerable<(int SourceLine, bool BlockStart)> moves, IReadOnlyDictionary<int, int>? expandedBlocks = null)
    {
        ArgumentNullException.ThrowIfNull(moves);
        var starts = new BlockStarts(expandedBlocks);
        foreach (var (line, blockStart) in moves)
        {
            if (starts.Next(line, blockStart))
            {
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
    public void Add(ExecutedMove move) => Add(move.SourceLine, move.BlockStart);

    /// <summary>Takes the source line of one finished move, and whether the move starts a block.</summary>
    public void Add(int sourceLine, bool blockStart)
    {
        lock (_lock)
        {
            if (!_starts.Next(sourceLine, blockStart))
            {
                return;
            }

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
