using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>What a block does on the controller, as far as tracking and the executed-move count care.</summary>
internal enum BlockMotion
{
    /// <summary>No move and no dwell (modes, M/T codes, data settings).</summary>
    None,

    /// <summary>Axis words that move the machine: one executed move.</summary>
    Move,

    /// <summary><c>G04</c>: a dwell, logged as one executed move by the simulator.</summary>
    Dwell,

    /// <summary>
    /// A program stop (<c>M00</c>, <c>M01</c>) without a move: written <c>M0==line DWELL0 M00</c>, so the tracking
    /// variable names the stop's line while the controller waits there, and the dwell is its one executed "move".
    /// </summary>
    Stop,
}

/// <summary>
/// Decides which blocks execute a move or a dwell. Kept small and separate so it can be swapped for the gcode
/// helper's interpreter. Rule: G04 is a dwell; otherwise a block with an X Y Z A B C word moves, unless a G code on
/// the same block takes the axis words as data (G10, G52, G92: on a PMAC their subroutines READ them, nothing moves).
/// PMAC starts in LINEAR mode, so axis words move even before any G00/G01. Stateless, so blocks are classified
/// alone (the splitter never looks back).
/// </summary>
internal static class MotionClassifier
{
    /// <summary>Classifies one block from its words; <paramref name="endsProgram"/> tells whether it carries M02/M30.</summary>
    public static BlockMotion Classify(ReadOnlySpan<GWord> words, out bool endsProgram)
    {
        var scan = default(MotionScan);
        foreach (ref readonly var w in words)
        {
            scan.Add(w);
        }

        endsProgram = scan.EndsProgram;
        return scan.Result;
    }
}

/// <summary>
/// <see cref="MotionClassifier.Classify"/> one word at a time, for a caller that already walks the block's words
/// (the splitter's emit loop): the same rule without a second pass over the words.
/// </summary>
internal struct MotionScan
{
    private bool _axis;
    private bool _dataOnly;
    private bool _dwell;

    /// <summary>The block carries M02 or M30.</summary>
    public bool EndsProgram { get; private set; }

    /// <summary>The first stop code of the block (<see cref="ProgramStopCodes"/>), or null.</summary>
    public string? StopCode { get; private set; }

    /// <summary>The block carries M06 (whose hook moves to the tool change position on a machine that has one).</summary>
    public bool ToolChange { get; private set; }

    /// <summary>What the words seen so far make of the block.</summary>
    public readonly BlockMotion Result => _dwell ? BlockMotion.Dwell : _axis && !_dataOnly ? BlockMotion.Move : StopCode is not null ? BlockMotion.Stop : BlockMotion.None;

    /// <summary>Takes one word of the block; <paramref name="stops"/> names the codes that stop the program (null: none).</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    public void Add(in GWord w, ProgramStopCodes? stops)
    {
        if (w.Letter == 'M' && StopCode is null && stops?.Find(w.CodeTimesTen) is { } stop)
        {
            StopCode = stop;
        }

        Add(w);
    }

    /// <summary>Takes one word of the block.</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    public void Add(in GWord w)
    {
        switch (w.Letter)
        {
            case 'G':
                switch (w.CodeTimesTen)
                {
                    case 40:
                        _dwell = true;
                        break;
                    case 100:
                    case 520:
                    case 920:
                    case 921:
                    case 922:
                    case 923:
                        _dataOnly = true;
                        break;
                }

                break;
            case 'M':
                if (w.CodeTimesTen is 20 or 300)
                {
                    EndsProgram = true;
                }

                ToolChange |= w.CodeTimesTen == 60;

                break;
            case 'X':
            case 'Y':
            case 'Z':
            case 'A':
            case 'B':
            case 'C':
                _axis = true;
                break;
        }
    }
}
