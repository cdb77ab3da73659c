namespace PmacStream.GCode;

/// <summary>The interpreter's view of the profile's codes: groups and their modality, roles, the words each code reads and needs.</summary>
public sealed partial class Interpreter
{
    private (int Motion, int Cycle) ClassifyGroups()
    {
        // One table lookup per word instead of the profile's letter set plus the letter tests in the hot loop.
        for (var c = 'A'; c <= 'Z'; c++)
        {
            _letterKinds[c - 'A'] = !_profile.AcceptsLetter(c) ? LetterKind.Unsupported
                : c == 'G' ? LetterKind.G
                : c == 'M' ? LetterKind.M
                : c is 'N' or 'O' or 'I' or 'J' or 'K' or 'R' or 'P' or 'Q' or 'L' or 'E' ? LetterKind.Parameter
                : LetterKind.Effective;
        }

        for (var i = 0; i < _gCount; i++)
        {
            _gNonModal[i] = !_profile.GGroups[i].Modal;
        }

        for (var i = 0; i < _mCount; i++)
        {
            _mNonModal[i] = !_profile.MGroups[i].Modal;
        }

        foreach (var def in _profile.GCodes)
        {
            _gInfo[def.Key] = new CodeInfo(def, _profile.GGroupOf(def.Number), CodeRoles.OfG(def.Key));
        }

        foreach (var def in _profile.MCodes)
        {
            _mInfo[def.Key] = new CodeInfo(def, _profile.MGroupOf(def.Number), GRole.Mode);
        }

        var motion = _profile.GGroupOf(1);
        _axisLineLetters = motion >= 0 && _letterKinds['N' - 'A'] == LetterKind.Parameter && _letterKinds['G' - 'A'] == LetterKind.G &&
            _letterKinds['X' - 'A'] == LetterKind.Effective && _letterKinds['Y' - 'A'] == LetterKind.Effective &&
            _letterKinds['Z' - 'A'] == LetterKind.Effective && !_gNonModal[motion];
        return (motion, _profile.GGroupOf(81));
    }

    private void ClearNonModal()
    {
        // Most blocks follow a block that set no non-modal code (G04, G53, M00...): nothing to clear then.
        if (!_nonModalSet)
        {
            return;
        }

        _nonModalSet = false;
        for (var i = 0; i < _gCount; i++)
        {
            if (_gNonModal[i] && _g[i] != null)
            {
                _g[i] = null;
                _dirty = true;
            }
        }

        for (var i = 0; i < _mCount; i++)
        {
            if (_mNonModal[i] && _m[i] != null)
            {
                _m[i] = null;
                _dirty = true;
            }
        }
    }

    private void SetG(int group, double value)
    {
        _nonModalSet |= _gNonModal[group];
        if (_g[group] != value)
        {
            _g[group] = value;
            _dirty = true;
        }
    }

    private void SetM(int group, double value)
    {
        _nonModalSet |= _mNonModal[group];
        if (_m[group] != value)
        {
            _m[group] = value;
            _dirty = true;
        }
    }

    private void ApplyG(int key, double? p)
    {
        switch (key)
        {
            case 170 or 180 or 190: _plane = key / 10; break;
            case 200: (_units, _scale) = (LengthUnits.Inches, 25.4); break;
            case 210: (_units, _scale) = (LengthUnits.Millimetres, 1.0); break;
            case 430 or 440: _lengthMode = key / 10; break;
            case 490: _lengthMode = 0; break;
            case 400 or 410 or 420: _compRequest = key / 10; break;
            case 900: _absolute = true; break;
            case 910: _absolute = false; break;
            case 901: _arcAbsolute = true; break;
            case 911: _arcAbsolute = false; break;
            case 930 or 940 or 950: _feedMode = key / 10; break;
            case 980: _returnToR = false; break;
            case 990: _returnToR = true; break;
            case (>= 540 and <= 590) or 591 or 592 or 593 or 541 or 1540: _coords.Select(key, p); break;
            default:
                if (ApplyTransformMode(key))
                {
                    break;
                }

                return;
        }

        _dirty = true;
    }

    /// <summary>The tool length the length code in force applies on Z (G43 +, G44 -, of tool H's length), into the work coordinates.</summary>
    private void UpdateToolLength() =>
        _coords.ToolLength = _lengthMode switch
        {
            43 => _coords.LengthOf(_h),
            44 => -_coords.LengthOf(_h),
            _ => 0,
        };

    /// <summary>Whether an M code of the block is one the host rewrites (M06 carries the tool to its routine) or converts.</summary>
    private bool MHost(Span<double> mIn, Span<int> mCol)
    {
        for (var mi = 0; mi < _mCount; mi++)
        {
            if (mCol[mi] != 0 && _mInfo[MachineProfile.Key(mIn[mi])].HostRewrites)
            {
                return true;
            }
        }

        return false;
    }

    /// <summary>Required words (E124), allowed values (E125) and "not yet on the controller" (W006) of one code of the block.</summary>
    private void CheckCode(in CodeInfo info, Span<int> col, Span<double> val, List<Diagnostic>? diags, int line, int column)
    {
        var def = info.Def;
        if (def.Controller == ControllerSupport.NotYet && _notYet.TryAdd(def.Code, line))
        {
            Add(diags, DiagnosticCodes.NotYetOnController, line, column, def.Code, def.Description, _profile.Name);
        }

        if (diags == null || (info.RequiresMask == 0 && def.Values.Count == 0))
        {
            return;
        }

        foreach (var c in def.Requires)
        {
            if (col[c - 'A'] == 0)
            {
                Add(diags, DiagnosticCodes.RequiredWordMissing, line, column, def.Code, c.ToString(), "the code needs it", "该代码需要它");
            }
        }

        foreach (var (c, set) in def.Values)
        {
            if (col[c - 'A'] != 0 && !set.Contains(val[c - 'A']))
            {
                Add(diags, DiagnosticCodes.ValueNotAllowed, line, col[c - 'A'], c, ModalState.Num(val[c - 'A']), def.Code, set.Text);
            }
        }
    }

    /// <summary>W003 for parameter words (I J K R P Q L E) no code of the block reads.</summary>
    private static void ReportUnusedWords(Span<int> col, int read, bool usedArcWords, bool usedP, bool effective, List<Diagnostic> diags, int line)
    {
        foreach (var c in "IJKRQLEP")
        {
            var bit = 1 << (c - 'A');
            if (col[c - 'A'] == 0 || (read & bit) != 0)
            {
                continue;
            }

            // I/J/K/R are arc words whatever else the block does; the others only count in a block that does something.
            var unused = c is 'I' or 'J' or 'K' or 'R' ? !usedArcWords : effective && (c != 'P' || !usedP);
            if (unused)
            {
                Add(diags, DiagnosticCodes.UnusedWord, line, col[c - 'A'], c);
            }
        }
    }

    /// <summary>The parameter words the motion code in force reads (an arc's I/J/K/R, LinuxCNC's P turns).</summary>
    private int MotionWords() =>
        _motionGroup >= 0 && _g[_motionGroup] is { } v && _gInfo.TryGetValue(MachineProfile.Key(v), out var info) && info.WordMask != 0
            ? info.WordMask
            : 1 << ('I' - 'A') | 1 << ('J' - 'A') | 1 << ('K' - 'A') | 1 << ('R' - 'A');

    /// <summary>A profile code as the interpreter uses it: its group, role and the letters it reads and needs as bit masks.</summary>
    private readonly struct CodeInfo(CodeDefinition def, int group, GRole role)
    {
        public CodeDefinition Def { get; } = def;

        public int Group { get; } = group;

        public GRole Role { get; } = role;

        public int WordMask { get; } = Mask(def.Words);

        public int RequiresMask { get; } = Mask(def.Requires);

        /// <summary>
        /// The host converts the code, or rewrites its block so that the library routine's READ finds its words right
        /// after the code (dwell, data settings, tool length, machine coordinates, cycles, reference returns, tool change,
        /// and every other library code that reads words: M19 R, G64 P Q ...). A move's own words are the controller's.
        /// </summary>
        public bool HostRewrites { get; } = def.Controller == ControllerSupport.Host ||
            (def.Controller == ControllerSupport.Library && def.Words.Length > 0 && role != GRole.Motion) ||
            (def.Code.StartsWith('M') ? def.Key == 60 : role is not (GRole.Mode or GRole.Motion) || def.Key is 430 or 440);

        public bool Reads(char letter) => (WordMask & (1 << (letter - 'A'))) != 0;

        private static int Mask(string letters)
        {
            var m = 0;
            foreach (var c in letters)
            {
                m |= 1 << (c - 'A');
            }

            return m;
        }
    }

    /// <summary>What the G codes of one block ask for, collected while they are applied.</summary>
    private struct BlockCodes
    {
        public bool Dwell;
        public int DwellColumn;
        public int MotionInBlock;   // 0..3 for G00..G03 in the block, -1 when none
        public int MotionColumn;
        public bool OtherMotion;    // G31, G38.x ...: this block moves to its point at feed
        public int Cycle;           // the cycle code's key in the block, 0 when none
        public int CycleColumn;
        public bool CycleCancel;
        public int Reference;       // G27/G28/G29/G30 key, 0 when none
        public bool MachineCoordinates;
        public int Data;            // the first axis-data code's key (G10, G52, G92 ...), 0 when none
        public int Read;            // parameter letters the block's codes read
        public bool Host;           // a code the host converts or rewrites (see CodeInfo.HostRewrites)

        public BlockCodes()
        {
            MotionInBlock = -1;
        }

        public void Add(in CodeInfo info, int key, int column)
        {
            Read |= info.WordMask;
            Host |= info.HostRewrites;
            switch (info.Role)
            {
                case GRole.Dwell:
                    Dwell = true;
                    DwellColumn = column;
                    break;
                case GRole.Motion when key is 0 or 10 or 20 or 30:
                    MotionInBlock = key / 10;
                    MotionColumn = column;
                    break;
                case GRole.Motion:
                    OtherMotion = true;
                    break;
                case GRole.Cycle:
                    Cycle = key;
                    CycleColumn = column;
                    break;
                case GRole.CycleCancel:
                    CycleCancel = true;
                    break;
                case GRole.Reference:
                    Reference = key;
                    break;
                case GRole.MachineCoordinates:
                    MachineCoordinates = true;
                    break;
                case GRole.AxisData when Data == 0:
                    Data = key;
                    break;
            }
        }
    }
}
