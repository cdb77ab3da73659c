using PmacStream.GCode;

namespace PmacStream.Program;

/// <summary>What a block does on the controller, as far as tracking and the executed-move count care.</summary>
internal enum BlockMotion
{
    /// <summary>No move and no dwell (modes, M/T codes, data settings).</summary>
    None,

    /// <summary>Axis words that move the machine: one executed move.</summary>
    Move,

    /// <summary><c>G04</c>: a dwell, logged as one executed move by the simulator.</summary>
    Dwell,
}

/// <summary>
/// Decides which blocks execute a move or a dwell. Kept small and separate so it can be swapped for the gcode
/// helper's interpreter. Rule: G04 is a dwell; otherwise a block with an X Y Z A B C word moves, unless a G code on
/// the same block takes the axis words as data (G10, G52, G92: on a PMAC their subroutines READ them, nothing moves).
/// PMAC starts in LINEAR mode, so axis words move even before any G00/G01.
/// </summary>
internal sealed class MotionClassifier
{
    /// <summary>Classifies one block (its words only; comments, N and O are irrelevant).</summary>
    public BlockMotion Classify(GBlock block)
    {
        var hasAxis = false;
        var dataOnly = false;
        var words = block.Words;
        for (var i = 0; i < words.Count; i++)
        {
            var w = words[i];
            switch (w.Letter)
            {
                case 'G':
                    switch (w.CodeTimesTen)
                    {
                        case 40:
                            return BlockMotion.Dwell;
                        case 100:
                        case 520:
                        case 920:
                        case 921:
                        case 922:
                        case 923:
                            dataOnly = true;
                            break;
                    }

                    break;
                case 'X':
                case 'Y':
                case 'Z':
                case 'A':
                case 'B':
                case 'C':
                    hasAxis = true;
                    break;
            }
        }

        return hasAxis && !dataOnly ? BlockMotion.Move : BlockMotion.None;
    }

    /// <summary>True when the block carries a program end code (M02 or M30).</summary>
    public static bool EndsProgram(GBlock block)
    {
        var words = block.Words;
        for (var i = 0; i < words.Count; i++)
        {
            if (words[i].Letter == 'M' && words[i].CodeTimesTen is 20 or 300)
            {
                return true;
            }
        }

        return false;
    }
}
