using System.Globalization;

namespace PmacStream.GCode.Expansion;

/// <content>Running one compiled line: blocks, assignments, FANUC flow and calls, RS274/NGC o-words.</content>
public sealed partial class MacroExpander
{
    private readonly Dictionary<(int File, int Line, string Keyword), int> _forward = [];

    private void Execute(MacroLine c, Frame f, int ln)
    {
        switch (c.Kind)
        {
            case LineKind.Raw:
                EmitRaw(f, ln);
                f.Pc = ln + 1;
                if (c.Words.Length > 0)
                {
                    _emittedBlock = f.Started = true;
                }

                if (c.EndsProgram)
                {
                    Finish();
                }

                break;
            case LineKind.TapeMark:
                if (f == _main && !_emittedBlock)
                {
                    EmitRaw(f, ln);
                    f.Pc = ln + 1;
                }
                else if (f == _main)
                {
                    Finish(); // the tape ends here
                }
                else if (!f.Started)
                {
                    f.Pc = ln + 1;
                }
                else
                {
                    throw Refuse(ExpansionCodes.Flow, 1, $"{Describe(f)} reaches the end of its tape (%) without {EndWord}", ln);
                }

                break;
            case LineKind.ProgramNumber:
                if (f == _main && !_emittedBlock && _main.ProgramNumber < 0)
                {
                    _main.ProgramNumber = c.ProgramNumber;
                    _main.ProgramStart = ln;
                    EmitRaw(f, ln);
                    f.Pc = ln + 1;
                }
                else if (f == _main)
                {
                    throw Refuse(ExpansionCodes.Flow, c.Column, $"the main program runs into O{c.ProgramNumber.ToString("D4", CultureInfo.InvariantCulture)} without M30 or M02", ln);
                }
                else if (!f.Started && c.ProgramNumber == f.ProgramNumber)
                {
                    f.Pc = ln + 1;
                }
                else
                {
                    throw Refuse(ExpansionCodes.Flow, c.Column, $"{Describe(f)} runs into O{c.ProgramNumber.ToString("D4", CultureInfo.InvariantCulture)} without M99", ln);
                }

                break;
            case LineKind.Words:
                _evaluating = c;
                EmitWords(c, f, ln);
                Assign(c);
                _emittedBlock = f.Started = true;
                f.Pc = ln + 1;
                if (c.EndsProgram)
                {
                    Finish();
                }

                break;
            case LineKind.Assign:
                _evaluating = c;
                Assign(c);
                f.Started = true;
                f.Pc = ln + 1;
                break;
            case LineKind.IfGoto:
                f.Started = true;
                if (Truth(c.Condition!))
                {
                    Goto(c, f, ln);
                }
                else
                {
                    f.Pc = ln + 1;
                }

                break;
            case LineKind.IfThen:
                f.Started = true;
                f.Pc = ln + 1;
                if (Truth(c.Condition!))
                {
                    var then = c.Then!;
                    _evaluating = then;
                    if (then.Kind == LineKind.Assign)
                    {
                        Assign(then);
                    }
                    else if (then.Kind is LineKind.Words or LineKind.Raw && then.Words.Length > 0)
                    {
                        EmitWords(then, f, ln);
                    }
                    else
                    {
                        throw Refuse(ExpansionCodes.Syntax, c.Column, "THEN takes an assignment or a block", ln);
                    }
                }

                break;
            case LineKind.Goto:
                f.Started = true;
                Goto(c, f, ln);
                break;
            case LineKind.While:
                f.Started = true;
                FanucWhile(c, f, ln);
                break;
            case LineKind.End:
                f.Started = true;
                FanucEnd(c, f, ln);
                break;
            case LineKind.Call:
                f.Started = true;
                FanucCall(c, f, ln);
                break;
            case LineKind.Return:
                FanucReturn(c, f, ln);
                break;
            case LineKind.OWord:
                f.Started = true;
                OWord(c, f, ln);
                break;
            case LineKind.ModalCall or LineKind.ModalCancel:
                ModalCall(c, f, ln);
                break;
        }

        if (_modalCall != null && c.Kind is LineKind.Raw or LineKind.Words && f == _modalOwner && !c.EndsProgram && MovesAxes(c.Words))
        {
            FanucCall(_modalCall, f, ln); // G66: after the move, the macro
        }
    }

    private string EndWord => _dialect == MacroDialect.Fanuc ? "M99" : "endsub";

    private bool Truth(MacroExpr e) => e.Num(this) != 0;

    private void Assign(MacroLine c)
    {
        var a = c.Assigns;
        if (a.Length == 0)
        {
            return;
        }

        if (a.Length == 1)
        {
            Write(a[0].Target, a[0].Value.Eval(this), c);
            return;
        }

        // RS274/NGC: the values of a line are all read before any is set.
        Span<double> values = a.Length <= 16 ? stackalloc double[a.Length] : new double[a.Length];
        for (var i = 0; i < a.Length; i++)
        {
            values[i] = a[i].Value.Eval(this);
        }

        for (var i = 0; i < a.Length; i++)
        {
            Write(a[i].Target, values[i], c);
        }
    }

    // ------------------------------------------------------------------ FANUC

    private void Goto(MacroLine c, Frame f, int ln)
    {
        var n = Math.Round(c.Target!.Num(this));
        var target = f.Source.FindN(n, f.ProgramStart, _dialect);
        if (target < 0)
        {
            throw Refuse(ExpansionCodes.Flow, c.Target.Column, $"GOTO {n.ToString(CultureInfo.InvariantCulture)}: no N{n.ToString(CultureInfo.InvariantCulture)} in {Describe(f)}", ln);
        }

        if (target <= ln && ++f.BackJumps > _o.MaxLoopIterations)
        {
            throw Refuse(ExpansionCodes.LoopLimit, c.Column, $"GOTO {n.ToString(CultureInfo.InvariantCulture)} went back more than {_o.MaxLoopIterations.ToString(CultureInfo.InvariantCulture)} times (the loop limit): an endless loop?", ln);
        }

        f.Loops.RemoveAll(l => l.Head > target || (l.End >= 0 && l.End < target));
        f.Pc = target;
    }

    private void FanucWhile(MacroLine c, Frame f, int ln)
    {
        var top = f.Loops.Count > 0 ? f.Loops[^1] : null;
        var again = top != null && top.Head == ln;
        var go = c.Condition == null || Truth(c.Condition);
        if (go)
        {
            if (again)
            {
                CountIteration(top!, c, ln);
            }
            else
            {
                f.Loops.Add(new Loop(ln, c.LoopId, string.Empty, "DO"));
            }

            f.Pc = ln + 1;
            return;
        }

        if (again)
        {
            f.Loops.RemoveAt(f.Loops.Count - 1);
        }

        ref var end = ref f.Source.Jump(ln);
        if (end == -2)
        {
            end = -1;
            for (var i = ln + 1; i < f.Source.LineCount; i++)
            {
                if (f.Source.Compiled(i, _dialect) is { } x && (x.Kind == LineKind.ProgramNumber || (x.Kind == LineKind.End && x.LoopId == c.LoopId)))
                {
                    end = x.Kind == LineKind.End ? i : -1;
                    break;
                }
            }
        }

        if (end < 0)
        {
            throw Refuse(ExpansionCodes.Flow, c.Column, $"DO{c.LoopId} without END{c.LoopId}", ln);
        }

        f.Pc = end + 1;
    }

    private void CountIteration(Loop l, MacroLine c, int ln)
    {
        if (++l.Iterations > _o.MaxLoopIterations)
        {
            throw Refuse(ExpansionCodes.LoopLimit, c.Column,
                $"the loop went round more than {_o.MaxLoopIterations.ToString(CultureInfo.InvariantCulture)} times (the loop limit): an endless loop?", ln);
        }
    }

    private void FanucEnd(MacroLine c, Frame f, int ln)
    {
        var i = f.Loops.Count - 1;
        while (i >= 0 && !(f.Loops[i].Id == c.LoopId && f.Loops[i].Kind == "DO"))
        {
            i--; // a loop, not a lambda: END runs once per iteration
        }

        if (i < 0)
        {
            throw Refuse(ExpansionCodes.Flow, c.Column, $"END{c.LoopId} without WHILE [...] DO{c.LoopId}", ln);
        }

        f.Loops.RemoveRange(i + 1, f.Loops.Count - i - 1);
        f.Loops[i].End = ln;
        f.Pc = f.Loops[i].Head;
    }

    /// <summary>
    /// G66 P L args: from now on every move block of this program calls the macro after its move, as G65 P L with the
    /// arguments as they were at G66 (FANUC evaluates them once); G67 ends it. Blocks of the macro itself, and of the
    /// subprograms the program calls, do not call it.
    /// </summary>
    private void ModalCall(MacroLine c, Frame f, int ln)
    {
        f.Started = true;
        if (c.Words.Length > 0)
        {
            EmitWords(c, f, ln); // the block's own words (not axis words: those would be a move) go as they are
            _emittedBlock = true;
        }

        f.Pc = ln + 1;
        if (c.Kind == LineKind.ModalCancel)
        {
            (_modalCall, _modalOwner) = (null, null);
            return;
        }

        if (MovesAxes(c.Words))
        {
            throw Refuse(ExpansionCodes.Syntax, c.Column, "G66 with axis words: a G66 block sets the modal call and moves nothing; move in the blocks after it", ln);
        }

        _modalCall = new MacroLine
        {
            Kind = LineKind.Call,
            Call = CallKind.G65,
            Column = c.Column,
            Target = new ConstExpr(c.Target!.Num(this)),
            Count = c.Count == null ? null : new ConstExpr(c.Count.Num(this)),
            Arguments = [.. c.Arguments.Select(a => (a.Variable, (MacroExpr)new ConstExpr(a.Value.Eval(this))))],
        };
        _modalOwner = f;
    }

    /// <summary>A block with an axis word: a move block, which calls a G66 macro after it.</summary>
    private static bool MovesAxes(MacroWord[] words)
    {
        foreach (var w in words)
        {
            if (w.Letter is 'X' or 'Y' or 'Z' or 'A' or 'B' or 'C' or 'U' or 'V' or 'W')
            {
                return true;
            }
        }

        return false;
    }

    private void FanucCall(MacroLine c, Frame f, int ln)
    {
        if (_modalCall != null && f == _modalOwner && !ReferenceEquals(c, _modalCall))
        {
            // The modal call of this frame's moves is proven (the same as a G65 after each move); whether the moves of a
            // program called under it call the macro too is not, so the host refuses rather than guess.
            throw Refuse(ExpansionCodes.Flow, c.Column, $"{c.Call} while a G66 modal call is in force: whether the moves of the program it calls call the G66 macro too is not expanded by the host; G67 before the call, G66 again after it", ln);
        }

        if (c.Words.Length > 0)
        {
            EmitWords(c, f, ln); // the block's own words run before the call
        }

        f.Pc = ln + 1;
        var p = (int)Math.Round(c.Target!.Num(this));
        var count = c.Count == null ? 1L : (long)Math.Round(c.Count.Num(this));
        if (count <= 0)
        {
            return;
        }

        if (_depth + 1 > _o.MaxCallDepth)
        {
            throw Refuse(ExpansionCodes.DepthLimit, c.Column, $"calls nested deeper than {_o.MaxCallDepth} (the call depth limit): a recursion without an end?", ln);
        }

        Frame callee;
        if (c.Call == CallKind.M97)
        {
            var at = f.Source.FindN(p, f.ProgramStart, _dialect);
            if (at < 0)
            {
                throw Refuse(ExpansionCodes.NotFound, c.Target.Column, $"M97 P{p}: no N{p} in {Describe(f)}", ln);
            }

            callee = new Frame(f.Source, at, f.Locals, f, ln) { ProgramStart = f.ProgramStart, Name = $"N{p}", ProgramNumber = f.ProgramNumber };
        }
        else
        {
            // FANUC's older format: P with more than four digits holds the repeat count before the program number.
            var (source, start) = LocateProgram(p, f);
            if (source == null && c.Count == null && p > 9999)
            {
                count = p / 10000;
                p %= 10000;
                (source, start) = LocateProgram(p, f);
            }

            if (source == null)
            {
                var folders = string.Join(", ", Folders());
                var names = string.Join(", ", _o.ProgramFileNames.Select(n => string.Format(CultureInfo.InvariantCulture, n, p)));
                throw Refuse(ExpansionCodes.NotFound, c.Target.Column, $"O{p.ToString("D4", CultureInfo.InvariantCulture)}: no such program in this file, nor as {names} in {folders}", ln);
            }

            double[] locals = f.Locals;
            if (c.Call == CallKind.G65)
            {
                locals = NewLocals();
                foreach (var (variable, value) in c.Arguments)
                {
                    locals[variable] = value.Eval(this);
                }
            }

            callee = new Frame(source, start, locals, f, ln)
            {
                ProgramStart = start,
                Name = $"O{p.ToString("D4", CultureInfo.InvariantCulture)}",
                ProgramNumber = p,
                Named = f.Named,
            };
        }

        callee.CallCount = count;
        callee.MapId = Map.AddFrame(f.MapId, callee.Source.Index, callee.Name, ln + 1, 1, (int)Math.Min(int.MaxValue, count));
        _depth++;
        _frame = callee;
    }

    private IEnumerable<string> Folders() =>
        _o.ProgramFolders.Count > 0 ? _o.ProgramFolders : [Path.GetDirectoryName(_main.Source.Path)!];

    private (ProgramSource? Source, int Start) LocateProgram(int p, Frame f)
    {
        var at = f.Source.FindProgram(p);
        if (at >= 0)
        {
            return (f.Source, at);
        }

        at = _main.Source.FindProgram(p);
        if (at >= 0)
        {
            return (_main.Source, at);
        }

        foreach (var folder in Folders())
        {
            foreach (var pattern in _o.ProgramFileNames)
            {
                var file = Path.GetFullPath(Path.Combine(folder, string.Format(CultureInfo.InvariantCulture, pattern, p)));
                if (File.Exists(file) && file != _main.Source.Path)
                {
                    var s = Source(file);
                    var o = s.FindProgram(p);
                    return (s, o >= 0 ? o : 0);
                }
            }
        }

        return (null, 0);
    }

    private void FanucReturn(MacroLine c, Frame f, int ln)
    {
        if (c.Words.Length > 0)
        {
            EmitWords(c, f, ln);
        }

        if (f == _main)
        {
            throw Refuse(ExpansionCodes.Flow, c.Column, "M99 in the main program repeats it endlessly on the control; the host does not stream that (end the program with M30)", ln);
        }

        if (f.CallNumber < f.CallCount && c.Target == null)
        {
            f.CallNumber++;
            f.Pc = f.Start;
            f.Loops.Clear();
            f.Started = false;
            f.MapId = Map.AddFrame(f.Caller!.MapId, f.Source.Index, f.Name, f.CallLine + 1, (int)Math.Min(int.MaxValue, f.CallNumber), (int)Math.Min(int.MaxValue, f.CallCount));
            return;
        }

        if (_modalCall != null && f == _modalOwner)
        {
            // G66 inside a subprogram is expanded for the subprogram's own moves; carried out to the caller's moves it is not.
            throw Refuse(ExpansionCodes.Flow, c.Column, "M99 with this subprogram's G66 modal call still in force: the host does not carry it to the caller's moves; G67 before M99", ln);
        }

        var caller = f.Caller!;
        _depth--;
        _frame = caller;
        if (c.Target != null)
        {
            var n = Math.Round(c.Target.Num(this));
            var at = caller.Source.FindN(n, caller.ProgramStart, _dialect);
            if (at < 0)
            {
                throw Make(ExpansionCodes.Flow, c.Target.Column, $"M99 P{n.ToString(CultureInfo.InvariantCulture)}: no N{n.ToString(CultureInfo.InvariantCulture)} in {Describe(caller)}", f, ln);
            }

            caller.Pc = at;
        }
    }

    // ------------------------------------------------------------------ RS274/NGC o-words

    private int Forward(Frame f, int ln, MacroLine c, params string[] keywords)
    {
        var key = (f.Source.Index, ln, keywords[0]);
        if (_forward.TryGetValue(key, out var at))
        {
            return at;
        }

        for (var i = ln + 1; i < f.Source.LineCount; i++)
        {
            if (f.Source.Compiled(i, _dialect) is { Kind: LineKind.OWord } x && x.Label == c.Label && Array.IndexOf(keywords, x.Keyword) >= 0)
            {
                _forward[key] = i;
                return i;
            }
        }

        throw Refuse(ExpansionCodes.Flow, c.Column, $"o{c.Label} {c.Keyword.ToLowerInvariant()} without o{c.Label} {keywords[^1].ToLowerInvariant()}", ln);
    }

    private void OWord(MacroLine c, Frame f, int ln)
    {
        switch (c.Keyword)
        {
            case "SUB":
                // A definition met in the flow is skipped; it runs when called.
                f.Pc = Forward(f, ln, c, "ENDSUB") + 1;
                break;
            case "ENDSUB" or "RETURN":
                OReturn(c, f, ln);
                break;
            case "CALL":
                OCall(c, f, ln);
                break;
            case "IF" or "ELSEIF" or "ELSE" or "ENDIF":
                OBranch(c, f, ln);
                break;
            case "WHILE":
                OWhile(c, f, ln);
                break;
            default:
                OLoop(c, f, ln);
                break;
        }
    }

    /// <summary>o-endsub and o-return: back to the caller, with the value returned (RS274/NGC's <c>_value</c>).</summary>
    private void OReturn(MacroLine c, Frame f, int ln)
    {
        if (f == _main)
        {
            throw Refuse(ExpansionCodes.Flow, c.Column, $"o{c.Label} {c.Keyword.ToLowerInvariant()} outside a call", ln);
        }

        _evaluating = c;
        _globalNames["_value_returned"] = c.OArgs.Length > 0 ? 1 : 0;
        if (c.OArgs.Length > 0)
        {
            _globalNames["_value"] = c.OArgs[0].Num(this);
        }

        _depth--;
        _frame = f.Caller!;
    }

    /// <summary>o-if, o-elseif, o-else, o-endif: the first branch whose condition holds runs, the others are passed.</summary>
    private void OBranch(MacroLine c, Frame f, int ln)
    {
        switch (c.Keyword)
        {
            case "IF":
                if (Truth(c.Condition!))
                {
                    f.Pc = ln + 1;
                    break;
                }

                for (var t = Forward(f, ln, c, "ELSEIF", "ELSE", "ENDIF"); ; t = Forward(f, t, c, "ELSEIF", "ELSE", "ENDIF"))
                {
                    var b = f.Source.Compiled(t, _dialect)!;
                    if (b.Keyword != "ELSEIF" || Truth(b.Condition!))
                    {
                        f.Pc = t + 1;
                        break;
                    }
                }

                break;
            case "ELSEIF":
            case "ELSE":
                f.Pc = Forward(f, ln, c, "ENDIF") + 1; // the branch before ran
                break;
            default: // ENDIF
                f.Pc = ln + 1;
                break;
        }
    }

    /// <summary>The loop statements but o-while: endwhile, do, repeat, endrepeat, break, continue.</summary>
    private void OLoop(MacroLine c, Frame f, int ln)
    {
        switch (c.Keyword)
        {
            case "ENDWHILE":
            {
                var l = FindLoop(f, c, ln, "WHILE");
                l.End = ln;
                f.Pc = l.Head;
                break;
            }

            case "DO":
                f.Loops.Add(new Loop(ln, 0, c.Label, "DO"));
                f.Pc = ln + 1;
                break;
            case "REPEAT":
            {
                var n = (long)Math.Round(c.Condition!.Num(this));
                if (n < 1)
                {
                    f.Pc = Forward(f, ln, c, "ENDREPEAT") + 1;
                    break;
                }

                f.Loops.Add(new Loop(ln, 0, c.Label, "REPEAT") { Left = n });
                f.Pc = ln + 1;
                break;
            }

            case "ENDREPEAT":
            {
                var l = FindLoop(f, c, ln, "REPEAT");
                if (--l.Left > 0)
                {
                    CountIteration(l, c, ln);
                    f.Pc = l.Head + 1;
                }
                else
                {
                    f.Loops.RemoveAt(f.Loops.Count - 1);
                    f.Pc = ln + 1;
                }

                break;
            }

            case "BREAK":
            {
                var l = FindLoop(f, c, ln, null);
                f.Loops.RemoveAt(f.Loops.Count - 1);
                f.Pc = LoopEnd(f, l, c) + 1;
                break;
            }

            case "CONTINUE":
            {
                var l = FindLoop(f, c, ln, null);
                // while: the condition again; repeat: its count; do: the condition at its end.
                f.Pc = l.Kind == "WHILE" ? l.Head : LoopEnd(f, l, c);
                break;
            }
        }
    }

    private int LoopEnd(Frame f, Loop l, MacroLine c) =>
        l.Kind switch
        {
            "WHILE" => Forward(f, l.Head, c, "ENDWHILE"),
            "REPEAT" => Forward(f, l.Head, c, "ENDREPEAT"),
            _ => Forward(f, l.Head, c, "WHILE"),
        };

    /// <summary>The loop of the statement's label (inner loops of other labels left, as RS274/NGC leaves them).</summary>
    private Loop FindLoop(Frame f, MacroLine c, int ln, string? kind)
    {
        var i = f.Loops.Count - 1;
        while (i >= 0 && !(f.Loops[i].Label == c.Label && (kind == null || f.Loops[i].Kind == kind)))
        {
            i--;
        }

        if (i < 0)
        {
            throw Refuse(ExpansionCodes.Flow, c.Column, $"o{c.Label} {c.Keyword.ToLowerInvariant()} outside its loop", ln);
        }

        f.Loops.RemoveRange(i + 1, f.Loops.Count - i - 1);
        return f.Loops[i];
    }

    private void OWhile(MacroLine c, Frame f, int ln)
    {
        ref var end = ref f.Source.Jump(ln);
        if (end == -2)
        {
            // A while with its own endwhile, or the end of a do ... while.
            end = -1;
            for (var i = ln + 1; i < f.Source.LineCount; i++)
            {
                if (f.Source.Compiled(i, _dialect) is { Kind: LineKind.OWord } x && x.Label == c.Label)
                {
                    end = x.Keyword == "ENDWHILE" ? i : -1;
                    break;
                }
            }
        }

        var top = f.Loops.Count > 0 ? f.Loops[^1] : null;
        if (end < 0)
        {
            if (top == null || top.Label != c.Label || top.Kind != "DO")
            {
                throw Refuse(ExpansionCodes.Flow, c.Column, $"o{c.Label} while without o{c.Label} endwhile or o{c.Label} do", ln);
            }

            if (Truth(c.Condition!))
            {
                CountIteration(top, c, ln);
                f.Pc = top.Head + 1;
            }
            else
            {
                f.Loops.RemoveAt(f.Loops.Count - 1);
                f.Pc = ln + 1;
            }

            return;
        }

        var again = top != null && top.Head == ln;
        if (Truth(c.Condition!))
        {
            if (again)
            {
                CountIteration(top!, c, ln);
            }
            else
            {
                f.Loops.Add(new Loop(ln, 0, c.Label, "WHILE") { End = end });
            }

            f.Pc = ln + 1;
        }
        else
        {
            if (again)
            {
                f.Loops.RemoveAt(f.Loops.Count - 1);
            }

            f.Pc = end + 1;
        }
    }

    private void OCall(MacroLine c, Frame f, int ln)
    {
        f.Pc = ln + 1;
        if (_depth + 1 > _o.MaxCallDepth)
        {
            throw Refuse(ExpansionCodes.DepthLimit, c.Column, $"calls nested deeper than {_o.MaxCallDepth} (the call depth limit): a recursion without an end?", ln);
        }

        var locals = NewLocals();
        _evaluating = c;
        for (var i = 0; i < c.OArgs.Length && i < 30; i++)
        {
            locals[i + 1] = c.OArgs[i].Num(this);
        }

        var (source, at) = LocateSub(c.Label, f);
        if (source == null)
        {
            throw Refuse(ExpansionCodes.NotFound, c.Column, $"o<{c.Label}> call: no o<{c.Label}> sub in this file, nor {c.Label}.ngc in {string.Join(", ", Folders())}", ln);
        }

        var name = char.IsAsciiDigit(c.Label[0]) ? $"o{c.Label}" : $"o<{c.Label}>";
        var callee = new Frame(source, at + 1, locals, f, ln) { ProgramStart = at + 1, Name = name, Named = [], Label = c.Label, Started = true };
        callee.MapId = Map.AddFrame(f.MapId, source.Index, name, ln + 1, 1, 1);
        _depth++;
        _frame = callee;
    }

    private (ProgramSource? Source, int Line) LocateSub(string label, Frame f)
    {
        var at = f.Source.FindSub(label);
        if (at >= 0)
        {
            return (f.Source, at);
        }

        at = _main.Source.FindSub(label);
        if (at >= 0)
        {
            return (_main.Source, at);
        }

        foreach (var folder in Folders())
        {
            var file = Path.GetFullPath(Path.Combine(folder, label + ".ngc"));
            if (File.Exists(file))
            {
                var s = Source(file);
                at = s.FindSub(label);
                if (at >= 0)
                {
                    return (s, at);
                }
            }
        }

        return (null, 0);
    }
}
