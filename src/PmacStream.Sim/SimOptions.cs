namespace PmacStream.Sim;

/// <summary>How fast the simulator's virtual clock runs when started with <see cref="PmacSimulator.StartClock"/>.</summary>
public readonly record struct SimSpeed
{
    private SimSpeed(double factor) => Multiplier = factor;

    /// <summary>Virtual seconds per real second; <see cref="double.PositiveInfinity"/> for instant.</summary>
    public double Multiplier { get; }

    /// <summary>True when moves execute as fast as lines arrive.</summary>
    public bool IsInstant => double.IsPositiveInfinity(Multiplier);

    /// <summary>One virtual second per real second.</summary>
    public static SimSpeed Realtime { get; } = new(1.0);

    /// <summary>Moves execute as fast as the host feeds lines; virtual time still advances by each move's duration.</summary>
    public static SimSpeed Instant { get; } = new(double.PositiveInfinity);

    /// <summary><paramref name="factor"/> virtual seconds per real second.</summary>
    public static SimSpeed Factor(double factor) =>
        factor > 0 ? new SimSpeed(factor) : throw new ArgumentOutOfRangeException(nameof(factor), "speed factor must be positive");

    /// <summary>Parses <c>realtime</c>, <c>instant</c> or <c>Nx</c> (e.g. <c>50x</c>).</summary>
    public static SimSpeed Parse(string text)
    {
        var t = text.Trim().ToLowerInvariant();
        if (t is "realtime" or "1x")
        {
            return Realtime;
        }

        if (t == "instant")
        {
            return Instant;
        }

        if (t.EndsWith('x') && double.TryParse(t[..^1], System.Globalization.NumberStyles.Float, System.Globalization.CultureInfo.InvariantCulture, out var f) && f > 0)
        {
            return Factor(f);
        }

        throw new FormatException($"speed '{text}': expected realtime, instant or Nx (e.g. 50x)");
    }

    /// <inheritdoc />
    public override string ToString() => IsInstant ? "instant" : Multiplier == 1.0 ? "realtime" : string.Create(System.Globalization.CultureInfo.InvariantCulture, $"{Multiplier:0.###}x");
}

/// <summary>What a rotary program does when execution catches up with the last line written (*assumed* behaviour).</summary>
public enum RotaryEndBehaviour
{
    /// <summary>Wait for more lines (a rotary buffer has no end); counts an underrun. The default (*assumed*).</summary>
    Wait,

    /// <summary>End the program when the buffer is closed and empty; waits (with underrun) only while it is open.</summary>
    EndWhenClosed,
}

/// <summary>Configuration of the simulated Turbo PMAC. Items marked *assumed* are not confirmed by a source (pmac-facts.md).</summary>
public sealed class SimOptions
{
    /// <summary>Moves calculated ahead of the executing move (PMAC lookahead). Default 2.</summary>
    public int LookaheadMoves { get; set; } = 2;

    /// <summary>ERR number answered when a rotary line does not fit. Default 6 (*assumed*).</summary>
    public int RotaryFullErrorCode { get; set; } = 6;

    /// <summary>
    /// When true, lines are also refused (with <see cref="RotaryFullErrorCode"/>) while the rotary-full bit is set
    /// (I17 lines ahead), not only when the words do not fit. Default false: the manual says the host normally stops
    /// at the full point "although this is not required" (*assumed*).
    /// </summary>
    public bool RefuseWhileFullBitSet { get; set; }

    /// <summary>I16 power-on value: the full bit clears below this many lines ahead. Default 5 (*assumed*).</summary>
    public int I16 { get; set; } = 5;

    /// <summary>I17 power-on value: the full bit sets at this many lines ahead. Default 10 (manual).</summary>
    public int I17 { get; set; } = 10;

    /// <summary>I3 of every new port (2: <c>DATA&lt;CR&gt;...&lt;ACK&gt;</c>).</summary>
    public int I3 { get; set; } = 2;

    /// <summary>I6 of every new port (1: errors as <c>&lt;BEL&gt;ERRnnn&lt;CR&gt;</c>).</summary>
    public int I6 { get; set; } = 1;

    /// <summary>I5 power-on value: PLC enable control (bit 0 PLC 0, bit 1 PLC 1..31). Default 3.</summary>
    public int I5 { get; set; } = 3;

    /// <summary>
    /// Rotary buffer size in words that coordinate system 1 has at power-on and after <c>$$$</c> (as if a start-up
    /// PLC defined it); 0 models a bare controller where the host must <c>DEFINE ROT</c>. Default 65536.
    /// </summary>
    public int DefaultRotWords { get; set; } = 65536;

    /// <summary>
    /// User memory for programs and buffers, words, as <c>SIZE</c> reports it less what the stored programs, PLCs and
    /// rotary buffers take: the standard 26K words by default, 212K (217,088) with the expanded memory option (Turbo PMAC2
    /// product description; docs/turbo-pmac-timing.md). *Assumed*: <c>DEFINE ROT</c> is not refused beyond it (the
    /// manual's error for that is not documented on the pages found), so a host must ask <c>SIZE</c> first.
    /// </summary>
    public int UserMemoryWords { get; set; } = StandardUserMemoryWords;

    /// <summary>The standard user memory, 26K words.</summary>
    public const int StandardUserMemoryWords = 26 * 1024;

    /// <summary>The expanded user memory option, 212K words.</summary>
    public const int ExpandedUserMemoryWords = 212 * 1024;

    /// <summary>Feed time unit in milliseconds (Isx90): F is in user units per this time. Default 60000 (per minute, G-code).</summary>
    public double FeedTimeUnitMs { get; set; } = 60000;

    /// <summary>Speed of RAPID moves in user units per feed time unit. Default 5000 (*assumed*).</summary>
    public double RapidFeed { get; set; } = 5000;

    /// <summary>Feed used before any F is programmed, units per feed time unit. Default 1000 (*assumed*).</summary>
    public double DefaultFeed { get; set; } = 1000;

    /// <summary>
    /// Isx87, the default acceleration time (ms) of blended LINEAR and CIRCLE moves until a program's <c>TA</c>.
    /// Default 0, the manual's (Turbo SRM p. 188: "0 (so Isx88 controls)"). See docs/turbo-pmac-timing.md.
    /// </summary>
    public double AccelerationTimeMs { get; set; }

    /// <summary>
    /// Isx88, the default S-curve time (ms) until a program's <c>TS</c>; the acceleration time is twice this when it
    /// is more than half of TA (Turbo SRM p. 188-189). Default 0 (*assumed*: a machine set up for contouring from
    /// G-code, which has no TA/TS words; the factory value is not in the pages we have).
    /// </summary>
    public double SCurveTimeMs { get; set; }

    /// <summary>
    /// Isx13, the segmentation time (ms). Default 10 (*assumed*, within the typical 5-20 ms, Turbo SRM p. 177):
    /// circles, cutter compensation and the lookahead need segmentation mode, and only in it may TA and TS both be 0
    /// (Turbo User Manual p. 276). It does not change move times here: blocks shorter than it are smoothed over, not
    /// lengthened (p. 177). 0 is accepted and changes nothing in the simulated path either.
    /// </summary>
    public double SegmentationTimeMs { get; set; } = 10;

    /// <summary>
    /// The shortest blended move when the acceleration time is 0 (TA and TS both 0), ms: 0.5 (Turbo SRM p. 188). So a
    /// Turbo PMAC runs at most 2,000 blended blocks a second, and so does the simulator.
    /// </summary>
    public double MinimumMoveTimeMs { get; set; } = 0.5;

    /// <summary>Feed-override slew rate in percent per second (Isx94/Isx95 analogue). Default 50 (*assumed*).</summary>
    public double OverrideSlewPercentPerSecond { get; set; } = 50;

    /// <summary>Virtual time between PLC scans, milliseconds. Default 1 (*assumed*).</summary>
    public double PlcScanIntervalMs { get; set; } = 1.0;

    /// <summary>Clock speed used by <see cref="PmacSimulator.StartClock"/>.</summary>
    public SimSpeed Speed { get; set; } = SimSpeed.Realtime;

    /// <summary>What a rotary program does when it runs out of lines. Default <see cref="RotaryEndBehaviour.Wait"/> (*assumed*).</summary>
    public RotaryEndBehaviour RotaryEndBehaviour { get; set; } = RotaryEndBehaviour.Wait;

    /// <summary>M-variable whose value is logged as each move's source line. Default 0 (M0).</summary>
    public int TrackingVariable { get; set; }

    /// <summary>
    /// When true, every rotary-buffer line the coordinate systems start calculating is logged
    /// (<see cref="PmacSimulator.ExecutedRotaryLines"/>), motion and non-motion alike, so tests can prove each program
    /// line ran exactly once. Off by default: the log grows with the program.
    /// </summary>
    public bool RecordRotaryLines { get; set; }

    /// <summary>
    /// When true (default), every executed move is kept in memory (<see cref="PmacSimulator.ExecutedMoves"/>): what
    /// tests read. A long-running host turns it off and takes the moves from <see cref="PmacSimulator.MoveExecuted"/>
    /// instead (an <see cref="ExecutedLogWriter"/> streaming them to disk, an <see cref="ExecutedLineCheck"/>), so memory
    /// does not grow with the program; the counters stay exact.
    /// </summary>
    public bool RetainExecutedMoves { get; set; } = true;

    /// <summary>Firmware version answered to <c>VERSION</c>.</summary>
    public string Version { get; set; } = SimInfo.Version;

    /// <summary>Answer to <c>CID</c> (card id). Default 602413.</summary>
    public int CardId { get; set; } = 602413;

    /// <summary>Answer to <c>TYPE</c>.</summary>
    public string TypeText { get; set; } = "TURBO2";

    /// <summary>Statements a program may run without producing a move before the calculation yields (runaway-loop guard).</summary>
    public int MaxStatementsPerCalculation { get; set; } = 100_000;

    /// <summary>
    /// Motors start with Home Complete set, as a machine with absolute encoders or one already homed. Default true (what
    /// the command line's built-in simulator and the tests use); <c>pmacstream sim</c> starts unhomed unless <c>--homed</c>.
    /// </summary>
    public bool StartHomed { get; set; } = true;

    /// <summary>
    /// The servo loop as a pure lag, milliseconds: the following error is the commanded velocity times this. Default 0
    /// (*assumed*: an ideal servo, actual = commanded); set it to see warning/fatal following error (Ixx12/Ixx11) at speed.
    /// </summary>
    public double ServoLagMs { get; set; }

    /// <summary>
    /// Step of the motors' own moves (jog, homing) and of the limit checks of program moves near a limit, milliseconds.
    /// Default 1 (*assumed*; a Turbo PMAC's servo cycle is about 0.44 ms): a limit stops a program within one step.
    /// </summary>
    public double MotorStepMs { get; set; } = 1.0;

    /// <summary>How far (counts) a motor may be from where a held program stopped for <c>R</c> to resume it (else ERR017). Default 0.5 (*assumed*).</summary>
    public double ResumePositionToleranceCounts { get; set; } = 0.5;

    /// <summary>
    /// An abort (a limit, a fault kill, <c>A</c>) that finds the executing move with every axis within this many counts
    /// of its end point, plus <see cref="AbortAtEndUnits"/>, finds it ended: the move is logged as executed and the axes
    /// stand at its end. Default 1/8 count (*assumed*): a controller reaches a move's end on a servo cycle, so it
    /// stands at the end exactly or a servo cycle's travel short of it (0.25 mm moves at F1500: 11 um); the host counts a
    /// block ended within half of this (Job: 1/16 count, positions reported to 1/32 count, SRM p. 260), so the two agree.
    /// </summary>
    public double AbortAtEndCounts { get; set; } = 0.125;

    /// <summary>Added to <see cref="AbortAtEndCounts"/>, axis units: the chunk files' end points are rounded to 5 decimals (10 nm). Default 2e-5.</summary>
    public double AbortAtEndUnits { get; set; } = 2e-5;

    /// <summary>
    /// A fault kill (fatal following error, amplifier fault) kills every motor of the motor's coordinate system, not only
    /// the motor. Default true (*assumed*: the choice a Turbo PMAC makes with Ixx24 bits 21-22, not simulated).
    /// </summary>
    public bool FaultKillsCoordinateSystem { get; set; } = true;

    /// <summary>Motors a Turbo PMAC has (numbered 1 to this).</summary>
    public const int MotorCount = MotorMap.Count;

    /// <summary>Home switch and hardware limit positions per motor number (*assumed*: what the machine has); motors not listed have the defaults.</summary>
    public IDictionary<int, MotorSettings> MotorSettings { get; } = new Dictionary<int, MotorSettings>();

    /// <summary>
    /// At power-on, motors 1-32 have Delta Tau's suggested definitions of their move registers where none is set:
    /// <c>Mxx61-&gt;D:</c> commanded, <c>Mxx62</c> actual and <c>Mxx63</c> target (end) position, in 1/(Ixx08*32) counts
    /// (<c>M163-&gt;D:$0000C7</c>; the motors' registers $80 apart, *assumed*). Default true: a controller set up with the
    /// suggested M-variable file, which the console reads distance to go from (docs/console.md).
    /// </summary>
    public bool SuggestedMVariables { get; set; } = true;

    /// <summary>Faults to inject, each at its time after a motion program first starts running (<c>pmacstream sim --inject</c>).</summary>
    public IList<FaultInjection> Faults { get; } = new List<FaultInjection>();
}
