using PmacStream.GCode;

namespace PmacStream.Preparation.Store;

/// <summary>
/// What a start from a block needs beyond the modal state of the block before it, as the program left it after the
/// block of <see cref="Line"/> (and for every block up to the next stored state): the offset from program to machine
/// coordinates in force, the highest Z reached so far, and what the controller must hold (the tables and shifts the
/// program's G10, G52 and G92 set, and a work offset selection the modal preamble cannot name). Stored once per change
/// in <c>exec_states</c>; line 0 is the power-on state before the first block.
/// </summary>
/// <param name="Line">The block after which this state holds (0: before the first block).</param>
/// <param name="Offset">Work offset + external offset + G52 + G92 + tool length, millimetres (the interpreter's <see cref="Interpreter.ActiveOffset"/>).</param>
/// <param name="HighestZ">The highest end Z of a move so far (machine coordinates), or null before any move.</param>
/// <param name="Controller">The lines restoring the controller's tables and shifts (the power-on state first).</param>
/// <param name="Selection">The selection of a work offset the modal preamble cannot name (G54.1 P, G59.1-G59.3), or null.</param>
public sealed record StoredExecState(int Line, Point3 Offset, double? HighestZ, IReadOnlyList<string> Controller, string? Selection)
{
    /// <summary>The controller lines as stored (one text, lines separated by a line feed).</summary>
    public string ControllerText => string.Join('\n', Controller);

    /// <summary>The same state (whatever the line it was taken after).</summary>
    public bool SameAs(StoredExecState other) =>
        other is not null && Offset == other.Offset && Nullable.Equals(HighestZ, other.HighestZ) && Selection == other.Selection
        && Controller.SequenceEqual(other.Controller, StringComparer.Ordinal);
}

/// <summary>
/// A start from a stored revision: the first motion block at or after the line asked for, the block before it (whose
/// modal state and end are where the start block begins; null when it is the program's first block), and the stored
/// state in force before it (null: the revision was stored before these states were, so the start must re-interpret).
/// </summary>
/// <param name="Block">The block started at.</param>
/// <param name="Previous">The block before it, or null.</param>
/// <param name="State">The execution state in force before the block, or null when the revision has none stored.</param>
public sealed record StoredStart(DecodedBlock Block, DecodedBlock? Previous, StoredExecState? State);

/// <summary>
/// Follows the import's interpreter and says when the state a start needs changed (<see cref="StoredExecState"/>):
/// cheap per block (a reference compare of the modal state, an offset and a Z), the full comparison only when the
/// modal state changed, which every G10, G52, G92, G43/G44/G49 and G54..G59 block does.
/// </summary>
internal sealed class ExecStateTracker
{
    private readonly MachineProfile _profile;
    private ModalState? _modal;
    private Point3 _offset;
    private double _highest = double.NegativeInfinity;
    private StoredExecState _last;

    /// <summary>Starts at the profile's power-on state (the state before the first block, line 0).</summary>
    public ExecStateTracker(MachineProfile profile)
    {
        _profile = profile;
        var interp = new Interpreter(profile);
        _last = Of(interp.Coordinates, interp.ActiveOffset, 0);
        Initial = _last;
        _modal = interp.State;
        _offset = interp.ActiveOffset;
    }

    /// <summary>The state before the first block.</summary>
    public StoredExecState Initial { get; }

    /// <summary>
    /// After the block of <paramref name="line"/>: the new state when it changed, else null. Its move, offset and tables
    /// as the canonical calls said them (<paramref name="decided"/>), its modal state the interpreter's snapshot.
    /// </summary>
    public StoredExecState? After(int line, ImportPipeline.Decisions decided, ModalState modal)
    {
        var highestChanged = false;
        if (decided.Moved && decided.Move.End.Z > _highest)
        {
            _highest = decided.Move.End.Z;
            highestChanged = true;
        }

        var offset = decided.Offset;
        if (!highestChanged && ReferenceEquals(modal, _modal) && offset == _offset)
        {
            return null;
        }

        _modal = modal;
        _offset = offset;
        var now = Of(decided.Tables!, offset, line);
        if (now.SameAs(_last))
        {
            return null;
        }

        _last = now;
        return now;
    }

    private StoredExecState Of(WorkCoordinates tables, Point3 offset, int line)
    {
        var (before, selection) = ControllerState.Of(tables, _profile);
        return new StoredExecState(line, offset, double.IsFinite(_highest) ? _highest : null, before, selection);
    }
}
