using PmacStream.Sim.Parsing;

namespace PmacStream.Sim;

internal enum BufferKind
{
    Prog,
    Plc,
    Rotary,
}

/// <summary>One stored program line: its text (for LIST) and compiled statements.</summary>
internal sealed class ProgramLine(string text, Stmt[] statements)
{
    public string Text { get; } = text;

    public Stmt[] Statements { get; } = statements;

    public int Words { get; } = CountWords(statements);

    private static int CountWords(Stmt[] statements)
    {
        var words = 0;
        foreach (var s in statements)
        {
            words += s.Words;
        }

        return Math.Max(1, words);
    }
}

/// <summary>
/// A motion program, PLC program or rotary buffer. Lines are addressed by absolute index; a rotary buffer frees
/// lines from the front as they are calculated (<see cref="BaseIndex"/> moves on).
/// </summary>
internal sealed class ProgramBuffer(BufferKind kind, int number, int capacityWords)
{
    private readonly List<ProgramLine> _lines = [];
    private Dictionary<int, (long Line, int Stmt)>? _labels;
    private readonly Dictionary<Stmt, (long Line, int Stmt)> _matches = new(ReferenceEqualityComparer.Instance);

    public BufferKind Kind { get; } = kind;

    public int Number { get; } = number;

    /// <summary>Capacity in words (rotary buffers); 0 = unlimited.</summary>
    public int CapacityWords { get; } = capacityWords;

    public int UsedWords { get; private set; }

    /// <summary>Open for new lines (rotary buffers stay executable while open).</summary>
    public bool IsOpen { get; set; }

    public long BaseIndex { get; private set; }

    private int _removedInList;

    /// <summary>One past the last line's absolute index.</summary>
    public long EndIndex => BaseIndex + (_lines.Count - _removedInList);

    public int LineCount => _lines.Count - _removedInList;

    public ProgramLine this[long index] => _lines[(int)(index - BaseIndex) + _removedInList];

    public bool Fits(int words) => CapacityWords <= 0 || UsedWords + words <= CapacityWords;

    public void Append(ProgramLine line)
    {
        _lines.Add(line);
        UsedWords += line.Words;
        _labels = null;
        _matches.Clear();
    }

    public void Clear()
    {
        BaseIndex = EndIndex;
        _lines.Clear();
        _removedInList = 0;
        UsedWords = 0;
        _labels = null;
        _matches.Clear();
    }

    /// <summary>Frees rotary lines before <paramref name="index"/> (they have been calculated).</summary>
    public void FreeBefore(long index)
    {
        while (BaseIndex < index && LineCount > 0)
        {
            UsedWords -= _lines[_removedInList].Words;
            _lines[_removedInList] = null!;
            _removedInList++;
            BaseIndex++;
        }

        if (_removedInList > 4096 && _removedInList > _lines.Count / 2)
        {
            _lines.RemoveRange(0, _removedInList);
            _removedInList = 0;
        }

        _labels = null;
        _matches.Clear();
    }

    public bool TryFindLabel(int label, out (long Line, int Stmt) position)
    {
        if (_labels is null)
        {
            _labels = [];
            for (var i = BaseIndex; i < EndIndex; i++)
            {
                var stmts = this[i].Statements;
                for (var j = 0; j < stmts.Length; j++)
                {
                    if (stmts[j] is LabelStmt l)
                    {
                        _labels.TryAdd(l.Label, (i, j));
                    }
                }
            }
        }

        return _labels.TryGetValue(label, out position);
    }

    /// <summary>
    /// Finds the statement that closes the block opened at (line, stmt): for IF its ELSE or ENDIF, for ELSE its ENDIF,
    /// for WHILE its ENDWHILE, for ENDWHILE its WHILE. Returns false when unmatched.
    /// </summary>
    public bool TryFindMatch(long line, int stmt, out (long Line, int Stmt) match)
    {
        var start = this[line].Statements[stmt];
        if (_matches.TryGetValue(start, out match))
        {
            return true;
        }

        var found = start is EndWhileStmt ? ScanBackward(line, stmt) : ScanForward(line, stmt, start is IfStmt);
        if (found is { } f)
        {
            _matches[start] = f;
            match = f;
            return true;
        }

        return false;
    }

    /// <summary>Checks IF/ELSE/ENDIF and WHILE/ENDWHILE balance (ERR009 on CLOSE).</summary>
    public bool IsStructured()
    {
        var stack = new Stack<Stmt>();
        for (var i = BaseIndex; i < EndIndex; i++)
        {
            foreach (var s in this[i].Statements)
            {
                switch (s)
                {
                    case IfStmt { SingleLine: false }:
                    case WhileStmt { SingleLine: false }:
                        stack.Push(s);
                        break;
                    case ElseStmt when stack.Count == 0 || stack.Peek() is not IfStmt:
                        return false;
                    case EndIfStmt when stack.Count == 0 || stack.Pop() is not IfStmt:
                        return false;
                    case EndWhileStmt when stack.Count == 0 || stack.Pop() is not WhileStmt:
                        return false;
                }
            }
        }

        return stack.Count == 0;
    }

    private (long, int)? ScanForward(long line, int stmt, bool fromIf)
    {
        var depth = 0;
        var j = stmt + 1;
        for (var i = line; i < EndIndex; i++, j = 0)
        {
            var stmts = this[i].Statements;
            for (; j < stmts.Length; j++)
            {
                switch (stmts[j])
                {
                    case IfStmt { SingleLine: false }:
                    case WhileStmt { SingleLine: false }:
                        depth++;
                        break;
                    case ElseStmt when depth == 0 && fromIf:
                        return (i, j);
                    case EndIfStmt or EndWhileStmt when depth == 0:
                        return (i, j);
                    case EndIfStmt or EndWhileStmt:
                        depth--;
                        break;
                }
            }
        }

        return null;
    }

    private (long, int)? ScanBackward(long line, int stmt)
    {
        var depth = 0;
        var j = stmt - 1;
        for (var i = line; i >= BaseIndex; i--)
        {
            var stmts = this[i].Statements;
            if (i != line)
            {
                j = stmts.Length - 1;
            }

            for (; j >= 0; j--)
            {
                switch (stmts[j])
                {
                    case EndIfStmt or EndWhileStmt:
                        depth++;
                        break;
                    case WhileStmt { SingleLine: false } when depth == 0:
                        return (i, j);
                    case IfStmt { SingleLine: false } or WhileStmt { SingleLine: false }:
                        depth--;
                        break;
                }
            }
        }

        return null;
    }
}
