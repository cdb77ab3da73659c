namespace PmacStream.Sim;

/// <summary>The kind of an executed move.</summary>
public enum MoveKind
{
    /// <summary>RAPID.</summary>
    Rapid,

    /// <summary>LINEAR.</summary>
    Linear,

    /// <summary>CIRCLE1 (clockwise about the NORMAL vector).</summary>
    Circle1,

    /// <summary>CIRCLE2 (counter-clockwise).</summary>
    Circle2,

    /// <summary>DWELL or DELAY.</summary>
    Dwell,
}

/// <summary>
/// One move (or dwell) the simulator finished. <see cref="SourceLine"/> is the tracking M-variable's value at the
/// start of the move (after that move's synchronous assignments), so <c>M0==i</c> placed before a move logs i.
/// </summary>
/// <param name="Sequence">1-based order of completion.</param>
/// <param name="SourceLine">Tracking variable (M0 by default) at the move's start.</param>
/// <param name="StartTime">Virtual start time, seconds.</param>
/// <param name="EndTime">Virtual end time, seconds.</param>
/// <param name="X">X at the end.</param>
/// <param name="Y">Y at the end.</param>
/// <param name="Z">Z at the end.</param>
/// <param name="Kind">Move kind.</param>
public readonly record struct ExecutedMove(long Sequence, int SourceLine, double StartTime, double EndTime, double X, double Y, double Z, MoveKind Kind)
{
    /// <summary>Coordinate system that ran the move.</summary>
    public int CoordinateSystem { get; init; }

    /// <summary>X at the start.</summary>
    public double StartX { get; init; }

    /// <summary>Y at the start.</summary>
    public double StartY { get; init; }

    /// <summary>Z at the start.</summary>
    public double StartZ { get; init; }

    /// <summary>Arc centre X (circle moves), else NaN.</summary>
    public double CenterX { get; init; }

    /// <summary>Arc centre Y (circle moves), else NaN.</summary>
    public double CenterY { get; init; }

    /// <summary>Arc centre Z (circle moves), else NaN.</summary>
    public double CenterZ { get; init; }

    /// <summary>Arc radius (circle moves), else 0.</summary>
    public double Radius { get; init; }

    /// <summary>Path length in user units (0 for dwells).</summary>
    public double Length { get; init; }

    /// <summary>Programmed feed in units per feed time unit (0 for rapids and dwells).</summary>
    public double Feed { get; init; }

    /// <summary>A, B, C at the end.</summary>
    public (double A, double B, double C) Rotary { get; init; }

    /// <summary>
    /// True for the move that starts a block: the first move after the synchronous assignment of the tracking variable
    /// (<c>M0==line</c>) fired. A block run twice in a row shows as two such moves of the same line, which the line
    /// alone cannot tell from one block of two moves.
    /// </summary>
    public bool BlockStart { get; init; }

    /// <summary>Duration in virtual seconds.</summary>
    public double Duration => EndTime - StartTime;
}

/// <summary>One rotary-buffer line a coordinate system started calculating (recorded with <see cref="SimOptions.RecordRotaryLines"/>).</summary>
/// <param name="Sequence">1-based order.</param>
/// <param name="CoordinateSystem">Coordinate system that ran it.</param>
/// <param name="Text">The line as stored.</param>
/// <param name="Time">Virtual time, seconds.</param>
public readonly record struct ExecutedRotaryLine(long Sequence, int CoordinateSystem, string Text, double Time);

/// <summary>Counters the tests and the CLI read to prove nothing was lost, repeated or reordered.</summary>
/// <param name="MovesExecuted">Moves and dwells completed.</param>
/// <param name="Underruns">Times the program was running, not at its end, and ran out of rotary lines with no motion left.</param>
/// <param name="Errors">ERR replies sent plus run-time program errors.</param>
/// <param name="LinesReceived">Program lines stored into any buffer.</param>
public readonly record struct SimCounters(long MovesExecuted, long Underruns, long Errors, long LinesReceived);
