using System.Text;

namespace PmacStream.GCode;

/// <summary>
/// The holes one cycle block (<see cref="MotionKind.Cycle"/>) drills: each one a rapid to its X/Y, a rapid down to the R
/// level, a feed to the bottom, back up to the block's end Z; with G91 the holes step evenly from the block's start to
/// its end, with G90 they are all at the end's X/Y.
/// </summary>
/// <param name="Count">Holes (the repeat count; 0 stores the cycle's data without drilling).</param>
/// <param name="RLevel">The R level (machine Z, program units) each hole starts its feed from.</param>
/// <param name="Bottom">The hole bottom (machine Z, program units).</param>
public readonly record struct CycleHoles(int Count, double RLevel, double Bottom);

/// <summary>
/// One interpreted block (a row of the program store's blocks table): source line, modal state after the block, its
/// words, and the geometry and time it means. Positions are absolute machine coordinates in program units (G90/G91 resolved,
/// work offset added). This is what start-from-line, the ETA, the preview and the program store read.
/// </summary>
public sealed record DecodedBlock
{
    /// <summary>1-based source line.</summary>
    public required int Line { get; init; }

    /// <summary>Byte offset of the line in the file (for seeking to start from this block).</summary>
    public long ByteOffset { get; init; }

    /// <summary>Sequence number (N) when the block has one.</summary>
    public double? N { get; init; }

    /// <summary>True when the line starts with <c>/</c> (block delete).</summary>
    public bool BlockDelete { get; init; }

    /// <summary>Modal state after this block.</summary>
    public required ModalState Modal { get; init; }

    /// <summary>X word as written (null when absent).</summary>
    public double? X { get; init; }

    /// <summary>Y word as written.</summary>
    public double? Y { get; init; }

    /// <summary>Z word as written.</summary>
    public double? Z { get; init; }

    /// <summary>I word (arc centre offset from the start, X).</summary>
    public double? I { get; init; }

    /// <summary>J word (arc centre offset, Y).</summary>
    public double? J { get; init; }

    /// <summary>K word (arc centre offset, Z).</summary>
    public double? K { get; init; }

    /// <summary>R word (arc radius; negative for more than 180 degrees).</summary>
    public double? R { get; init; }

    /// <summary>F word.</summary>
    public double? F { get; init; }

    /// <summary>S word.</summary>
    public double? S { get; init; }

    /// <summary>T word.</summary>
    public double? T { get; init; }

    /// <summary>H word.</summary>
    public double? H { get; init; }

    /// <summary>D word.</summary>
    public double? D { get; init; }

    /// <summary>P word (dwell time with G04).</summary>
    public double? P { get; init; }

    /// <summary>What the block does.</summary>
    public MotionKind Motion { get; init; }

    /// <summary>Absolute position before the block.</summary>
    public Point3 Start { get; init; }

    /// <summary>Absolute position after the block.</summary>
    public Point3 End { get; init; }

    /// <summary>Arc centre (absolute; the plane's third axis at the start value) for arcs, else null.</summary>
    public Point3? Center { get; init; }

    /// <summary>Path length in program units (arc length, with the helical part, for arcs).</summary>
    public double Length { get; init; }

    /// <summary>Estimated time: length at the programmed feed, rapids at the profile rapid rate, dwells as programmed.</summary>
    public double DurationSeconds { get; init; }

    /// <summary>
    /// The block as self-contained G-code: the sequence number, the code in force in every G group of the profile,
    /// the words the block carries, then the M codes in force. Modal codes that take a block's axis words as data
    /// (scaling, mirror, rotation, modal macro call) are left out: they stay in force, and written again they would
    /// make this block's move their data. Reading this text back in the same prior state yields an equal block
    /// (the property tests check it); repeating modal codes is harmless to the controller.
    /// </summary>
    public string ToGCode()
    {
        var sb = new StringBuilder(64);
        void W(char letter, double? v)
        {
            if (v is { } value)
            {
                if (sb.Length > 0)
                {
                    sb.Append(' ');
                }

                sb.Append(letter).Append(ModalState.Num(value));
            }
        }

        void Code(char letter, double? v)
        {
            if (v is { } value)
            {
                sb.Append(sb.Length > 0 ? " " : string.Empty).Append(letter).Append(value < 10 ? "0" : string.Empty).Append(ModalState.Num(value));
            }
        }

        W('N', N);
        for (var g = 0; g < Modal.G.Count; g++)
        {
            if (Modal.G[g] is not { } v || !CodeRoles.ReadsAxesWhileInForce(MachineProfile.Key(v)))
            {
                Code('G', Modal.G[g]);
            }
        }

        W('X', X);
        W('Y', Y);
        W('Z', Z);
        W('I', I);
        W('J', J);
        W('K', K);
        W('R', R);
        W('F', F);
        W('S', S);
        W('T', T);
        W('H', H);
        W('D', D);
        W('P', P);
        for (var m = 0; m < Modal.M.Count; m++)
        {
            Code('M', Modal.M[m]);
        }

        return sb.ToString();
    }
}
