using System.Globalization;
using System.Text.RegularExpressions;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Preparation;

/// <summary>What starting at a block needs: the state before it, where it starts, and the preamble to get there safely.</summary>
/// <param name="Line">The source line of the block started at (the first motion block at or after the requested line).</param>
/// <param name="State">Modal state in force before that block (units, plane, distance mode, work offset, tool, length offset, spindle, coolant, feed).</param>
/// <param name="Start">Where the block starts (the end of the move before it), program coordinates.</param>
/// <param name="GCode">The preamble as G-code, for showing to the operator.</param>
/// <param name="PmacLines">The preamble as rotary-buffer lines (feed through the feed variable in paper mode).</param>
public sealed record StartPlan(int Line, ModalState State, Point3 Start, IReadOnlyList<string> GCode, IReadOnlyList<string> PmacLines)
{
    /// <summary>The Z retracted to before moving in XY (work coordinates).</summary>
    public double SafeZ { get; init; }
}

/// <summary>Where the preamble retracts to before it moves in XY.</summary>
public enum SafeZMode
{
    /// <summary>A fixed height (<see cref="StartPlanOptions.SafeZ"/>, work coordinates).</summary>
    Fixed,

    /// <summary>
    /// The highest Z the program reached before the block plus <see cref="StartPlanOptions.Clearance"/> (work
    /// coordinates of the active offset); the fixed height when nothing moved yet.
    /// </summary>
    HighestSoFar,
}

/// <summary>How a start from a line is planned; the CLI and the HMI use the same options, so they show the same preamble.</summary>
public sealed record StartPlanOptions
{
    /// <summary>How the safe Z is chosen.</summary>
    public SafeZMode SafeZMode { get; init; } = SafeZMode.Fixed;

    /// <summary>Fixed safe Z, work coordinates (and the fallback of <see cref="SafeZMode.HighestSoFar"/>). Default 10.</summary>
    public double SafeZ { get; init; } = 10;

    /// <summary>Added to the highest Z so far in <see cref="SafeZMode.HighestSoFar"/> mode. Default 5.</summary>
    public double Clearance { get; init; } = 5;

    /// <summary>How feed reaches the controller (paper: <c>P500=</c> plus <c>F(P500)</c> on moves).</summary>
    public FeedMode FeedMode { get; init; } = FeedMode.Paper;

    /// <summary>The feed variable (P500).</summary>
    public string FeedVariable { get; init; } = "P500";

    /// <summary>
    /// Block delete as the program runs (the split's <see cref="ChunkShape.BlockDelete"/>): on, the blocks starting with
    /// <c>/</c> (and the rest of a block after a <c>/</c> in it) never ran, so the state and position a start restores
    /// must not count them. Off (the default here, and what the store decodes): every block ran.
    /// </summary>
    public bool BlockDelete { get; init; }

    /// <summary>Machine profile for the interpreter (work offsets, codes); null: the seed-002 mill.</summary>
    public MachineProfile? Profile { get; init; }

    /// <summary>The options for a split program: its feed mode and feed variable, the rest from <paramref name="baseOptions"/>.</summary>
    public static StartPlanOptions For(ChunkManifest manifest, StartPlanOptions? baseOptions = null) =>
        (baseOptions ?? new StartPlanOptions()) with
        {
            FeedMode = manifest.Feed,
            FeedVariable = string.IsNullOrWhiteSpace(manifest.FeedVariable) ? "P500" : manifest.FeedVariable.Trim(),
            // A manifest without its shape was split with the splitter's default: block delete on.
            BlockDelete = manifest.Shape?.BlockDelete ?? true,
        };
}

/// <summary>
/// "Start from any block" (an HMI command, and resume after an abort): replays the source through the
/// interpreter up to the block, then builds a preamble that restores the modal state and approaches safely:
/// retract to a safe Z, rapid in XY to the block's start, feed down to its Z, then the distance mode, motion mode and feed.
/// </summary>
public static class StartFromLine
{
    private static readonly Regex FWord = new(@"(?<![A-Z])F\s*([-+]?[\d.]+)", RegexOptions.IgnoreCase | RegexOptions.CultureInvariant);
    private static readonly Regex AxisWord = new(@"(?<![A-Z])[XYZ]\s*[-+]?[\d.]", RegexOptions.IgnoreCase | RegexOptions.CultureInvariant);

    /// <summary>Plans a start at the first motion block at or after <paramref name="line"/> with a fixed safe Z.</summary>
    /// <param name="sourcePath">The G-code source.</param>
    /// <param name="line">Requested source line.</param>
    /// <param name="safeZ">Safe height to retract to before moving in XY (work coordinates).</param>
    /// <param name="feedMode">How feed reaches the controller (paper: <c>P500=</c> plus <c>F(P500)</c> on moves).</param>
    /// <param name="feedVariable">The feed variable (P500).</param>
    /// <param name="profile">Machine profile for the interpreter (default: the seed-002 mill).</param>
    /// <exception cref="ArgumentOutOfRangeException">No motion block at or after the line.</exception>
    public static StartPlan Plan(string sourcePath, int line, double safeZ = 10, FeedMode feedMode = FeedMode.Paper, string feedVariable = "P500", MachineProfile? profile = null) =>
        Plan(sourcePath, line, new StartPlanOptions { SafeZ = safeZ, FeedMode = feedMode, FeedVariable = feedVariable, Profile = profile });

    /// <summary>
    /// Plans a start at the first motion block at or after <paramref name="line"/>: replays the source through the
    /// interpreter to the state and position before that block, then builds the preamble (<see cref="Build"/>) with
    /// the block's start and the safe Z in work coordinates of the active work offset. The one planner of the CLI
    /// (<c>--from-line</c>, <c>resume</c>) and the HMI (start from the selected line, resume after an abort).
    /// </summary>
    /// <exception cref="ArgumentOutOfRangeException">No motion block at or after the line.</exception>
    public static StartPlan Plan(string sourcePath, int line, StartPlanOptions options, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(options);
        var profile = options.Profile ?? MachineProfile.Default;
        var decided = new PlannedBlock(profile);
        var interp = new Interpreter(profile) { Canon = decided, BlockDeleteEnabled = options.BlockDelete };
        var highest = double.NegativeInfinity;
        // An expanded program's lines (subprograms, macros, loops) are its expanded lines, as M0== counts them.
        using var reader = GCode.Expansion.ProgramExpansion.OpenReader(sourcePath, profile);
        var count = 0;
        while (reader.Read())
        {
            if ((++count & 0xFFF) == 0)
            {
                cancellationToken.ThrowIfCancellationRequested();
            }

            var block = reader.Current;
            var before = interp.State; // the modal snapshot the block starts from
            // What the controller must hold (tables, shifts) as the blocks before this one left it: taken at the line's
            // start, for the blocks from the requested line on only (the start is the first that moves).
            decided.Watch = block.LineNumber >= line;
            var moved = interp.Execute(block) && decided.Moved;
            if (block.LineNumber >= line && moved)
            {
                // Work coordinates of the offset in force (work offset, shifts, tool length: what the controller's
                // displacement holds): the preamble's G90 moves run under it. Millimetres, as positions are.
                var offset = decided.Start.Offset;
                var startWork = decided.Start.Position - offset;
                var safeZ = options.SafeZMode == SafeZMode.HighestSoFar && double.IsFinite(highest)
                    ? highest - offset.Z + options.Clearance
                    : options.SafeZ;

                // The block's own F travels on a feed-variable line before its marker line, which a start at the
                // block skips: the preamble's feed is the one the block runs with.
                var feedState = decided.Feed is { } blockFeed && blockFeed != before.Feed ? before with { Feed = blockFeed } : before;
                return BuildCore(block.LineNumber, before, feedState, startWork, safeZ, options.FeedMode, options.FeedVariable, decided.Controller);
            }

            if (moved)
            {
                // Ends only: each move starts where the previous ended, and the first starts at the interpreter's
                // initial position, which is not a place the program took the tool to.
                highest = Math.Max(highest, decided.End.Z);
            }
        }

        throw new ArgumentOutOfRangeException(nameof(line), $"{sourcePath}: no motion block at or after line {line}");
    }

    /// <summary>
    /// Plans a start at the first motion block at or after <paramref name="line"/> of a stored revision, from what the
    /// import stored instead of interpreting from the top: the modal state and end of the block before it, the
    /// execution state in force there (<see cref="StoredExecState"/>: offsets, shifts, tables, highest Z). Gives the
    /// plan <see cref="Plan(string, int, StartPlanOptions, CancellationToken)"/> gives for the revision's source.
    /// </summary>
    /// <exception cref="ArgumentOutOfRangeException">No motion block at or after the line.</exception>
    /// <exception cref="StoredStateMissingException">The revision was stored without its execution states (before schema 7).</exception>
    public static StartPlan Plan(IProgramRevisions store, long programId, int line, StartPlanOptions options)
    {
        ArgumentNullException.ThrowIfNull(store);
        ArgumentNullException.ThrowIfNull(options);
        var start = store.GetStart(programId, line)
            ?? throw new ArgumentOutOfRangeException(nameof(line), $"program {programId}: no motion block at or after line {line}");
        var exec = start.State ?? throw new StoredStateMissingException(programId);
        if (options.BlockDelete && store.HasBlockDeleteBlock(programId, start.Block.Line))
        {
            // The store decoded every block; with block delete on, a '/' block up to the start never ran.
            throw new StoredStateMissingException(programId,
                $"program {programId} has a block-delete block at or before line {start.Block.Line}, which the store decodes and block delete skips");
        }

        ModalState before;
        Point3 position;
        if (start.Previous is { } previous)
        {
            (before, position) = (previous.Modal, previous.End);
        }
        else
        {
            var fresh = new Interpreter(options.Profile ?? MachineProfile.Default);
            (before, position) = (fresh.State, fresh.Position);
        }

        var offset = exec.Offset;
        var safeZ = options.SafeZMode == SafeZMode.HighestSoFar && exec.HighestZ is { } highest
            ? highest - offset.Z + options.Clearance
            : options.SafeZ;
        var block = start.Block;
        var feedState = block.Modal.Feed is { } blockFeed && blockFeed != before.Feed ? before with { Feed = blockFeed } : before;
        return BuildCore(block.Line, before, feedState, position - offset, safeZ, options.FeedMode, options.FeedVariable, (exec.Controller, exec.Selection));
    }

    /// <summary>
    /// Builds the preamble for a known state and start point (work coordinates): the modal state (units, plane, work
    /// offset, tool and length offset, spindle direction and speed, coolant), retract to the safe Z, rapid in XY,
    /// feed down to the block's Z, then distance mode, motion mode and feed.
    /// </summary>
    public static StartPlan Build(int line, ModalState state, Point3 start, double safeZ, FeedMode feedMode = FeedMode.Paper, string feedVariable = "P500") =>
        BuildCore(line, state, state, start, safeZ, feedMode, feedVariable, default);

    /// <summary>
    /// The planner's canonical sink: where the line starts (position, offset, and the controller's tables when the
    /// planner watches it), whether it moved and where it ended, and the feed it leaves.
    /// </summary>
    private sealed class PlannedBlock(MachineProfile profile) : ICanonicalMoves
    {
        /// <summary>Set before a line from the requested one on: its start reads the tables the controller must hold.</summary>
        public bool Watch { get; set; }

        public CanonStart Start { get; private set; }

        public (IReadOnlyList<string>? Before, string? Selection) Controller { get; private set; }

        public bool Moved { get; private set; }

        public Point3 End { get; private set; }

        public double? Feed { get; private set; }

        public void StartBlock(in CanonStart start)
        {
            (Start, Moved) = (start, false);
            Controller = Watch ? ControllerState.Of(start.Tables, profile) : default;
        }

        public void Step(in HostMove step)
        {
        }

        public void Motion(in CanonMotion motion) => (Moved, End) = (true, motion.End);

        public void EndBlock(in CanonBlock block) => Feed = block.Feed;
    }

    private static StartPlan BuildCore(int line, ModalState state, ModalState preambleState, Point3 start, double safeZ, FeedMode feedMode, string feedVariable,
        (IReadOnlyList<string>? Before, string? Selection) controller)
    {
        var modal = preambleState.ToPreamble(null, forController: true).ToList();
        var last = modal[^1];
        modal.RemoveAt(modal.Count - 1);
        if (controller.Selection is { } selection)
        {
            modal.Insert(1, selection); // after the plane and G54..G59 line, which cannot name it
        }

        var restore = controller.Before ?? [];
        var unit = preambleState.Units == LengthUnits.Inches ? 25.4 : 1.0;
        var approachFeed = preambleState.Feed is > 0 ? Math.Min(preambleState.Feed.Value * unit, 500) : 300;
        var z = Math.Max(safeZ, start.Z);
        // Tables and shifts go as the library reads them (no feed word); the rest as the splitter translates it.
        var gcode = new List<string>(restore.Count + modal.Count + 4);
        gcode.AddRange(restore.Select(l => l == HostConversion.PowerOnState ? l + " (the library's power-on state: G54, no G52/G92 shift, G49, G90)" : l));
        gcode.AddRange(modal);
        gcode.AddRange(new[]
        {
            $"G90 G00 Z{Num(z)}",
            $"G00 X{Num(start.X)} Y{Num(start.Y)}",
            $"G01 Z{Num(start.Z)} F{Num(approachFeed)}",
            last,
        });

        var pmac = new List<string>(restore);
        foreach (var g in gcode.Skip(restore.Count))
        {
            pmac.AddRange(ToPmac(g, feedMode, feedVariable));
        }

        return new StartPlan(line, state, start, gcode, pmac) { SafeZ = z };
    }

    /// <summary>Translates a preamble G-code line as the splitter does: in paper mode F becomes <c>P500=</c> and moves carry <c>F(P500)</c>.</summary>
    public static IEnumerable<string> ToPmac(string gcode, FeedMode feedMode, string feedVariable)
    {
        if (feedMode != FeedMode.Paper)
        {
            yield return gcode;
            yield break;
        }

        var f = FWord.Match(gcode);
        if (f.Success)
        {
            yield return $"{feedVariable}={f.Groups[1].Value}";
            gcode = FWord.Replace(gcode, string.Empty).Trim();
            gcode = Regex.Replace(gcode, @"\s+", " ");
        }

        if (gcode.Length == 0)
        {
            yield break;
        }

        yield return AxisWord.IsMatch(gcode) ? $"{gcode} F({feedVariable})" : gcode;
    }

    private static string Num(double v) => Math.Round(v, 4).ToString("0.####", CultureInfo.InvariantCulture);
}

/// <summary>
/// The store does not hold the state a start needs: a revision stored before its execution states were (schema 7), or
/// one whose stored states count blocks that block delete skips. A start from it must re-interpret the source.
/// </summary>
public sealed class StoredStateMissingException(long programId, string? message = null)
    : InvalidOperationException(message ?? $"program {programId} was stored without the execution states a start reads (imported before schema 7)")
{
    /// <summary>The revision.</summary>
    public long ProgramId { get; } = programId;
}
