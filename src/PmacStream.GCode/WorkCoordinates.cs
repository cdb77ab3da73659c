namespace PmacStream.GCode;

/// <summary>
/// Where program coordinates lie in machine coordinates: the selected work offset (G54..G59, the extended G54.1 P /
/// G154 P ones) with the values G10 set, plus the local shift of G52 and the G92 shift. The interpreter's positions
/// are machine coordinates, so a program coordinate is the machine one minus <see cref="Active"/>. Only the
/// interpreter changes them; its callers read them (<see cref="CanonBlock.Tables"/>).
/// </summary>
public sealed class WorkCoordinates
{
    private readonly MachineProfile _profile;
    private Dictionary<int, Point3>? _set; // offsets G10 changed, by key (540 for G54, 5410+P for G54.1 Pn)
    private Point3 _external; // FANUC's external work offset (G10 L2 P0), added to every work coordinate system
    private Point3 _local;
    private Point3 _shift;
    private double _toolLength;
    private Dictionary<int, double>? _tools; // tool lengths G10 changed, by H number
    private Dictionary<int, double>? _wear;  // FANUC G10 L11 wear, added to the length
    private Point3 _active;   // valid while _known: a Nullable<Point3> read stalled on store forwarding in the hot path
    private bool _known;

    internal WorkCoordinates(MachineProfile profile, int code)
    {
        _profile = profile;
        Selected = code * 10;
    }

    /// <summary>The selected work offset as a key: 540..590 for G54..G59, 5410 + P for G54.1 P / G154 P.</summary>
    public int Selected { get; private set; }

    /// <summary>The whole offset from program to machine coordinates (work offset + external offset + G52 + G92), looked up once per change.</summary>
    public Point3 Active
    {
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        get => _known ? _active : Compute();
    }

    private Point3 Compute()
    {
        _active = Offset(Selected) + _external + _local + _shift + new Point3(0, 0, _toolLength);
        _known = true;
        return _active;
    }

    /// <summary>Selects G54..G59 (<paramref name="key"/> 540..590) or an extended offset (G54.1 P, G154 P).</summary>
    internal void Select(int key, double? p)
    {
        var selected = key is 541 or 1540 && p is { } n ? 5410 + (int)n : key;
        if (selected != Selected)
        {
            Selected = selected;
            _known = false;
        }
    }

    /// <summary>
    /// G10 L2/L20: sets work offset <paramref name="p"/> (0: the selected one, or FANUC's external offset where the
    /// profile has one; 1..6: G54..G59, 7..9: G59.1..G59.3 with LinuxCNC; the extended ones with
    /// <paramref name="extended"/>) on the given axes, to the values or, with <paramref name="fromPosition"/>, so that
    /// <paramref name="position"/> reads as the values.
    /// </summary>
    internal void SetOffset(int p, bool extended, bool fromPosition, double? x, double? y, double? z, Point3 position)
    {
        if (p == 0 && !extended && !fromPosition && _profile.ExternalWorkOffset)
        {
            _external = new Point3(x ?? _external.X, y ?? _external.Y, z ?? _external.Z);
            _known = false;
            return;
        }

        var key = extended ? 5410 + p : p == 0 ? Selected : p <= 6 ? 530 + (p * 10) : 590 + (p - 6);
        var old = Offset(key);
        var shift = _external + _local + _shift + new Point3(0, 0, _toolLength);
        var value = fromPosition
            ? new Point3(x is { } ax ? position.X - ax - shift.X : old.X, y is { } ay ? position.Y - ay - shift.Y : old.Y, z is { } az ? position.Z - az - shift.Z : old.Z)
            : new Point3(x ?? old.X, y ?? old.Y, z ?? old.Z);
        (_set ??= new())[key] = value;
        _known = false;
    }

    /// <summary>G52: the local shift on the given axes (0 cancels it).</summary>
    internal void SetLocal(double? x, double? y, double? z)
    {
        _local = new Point3(x ?? _local.X, y ?? _local.Y, z ?? _local.Z);
        _known = false;
    }

    /// <summary>G92: shifts coordinates so that <paramref name="position"/> reads as the given values.</summary>
    internal void SetShift(double? x, double? y, double? z, Point3 position)
    {
        var o = Offset(Selected) + _external + _local + new Point3(0, 0, _toolLength);
        _shift = new Point3(x is { } ax ? position.X - ax - o.X : _shift.X, y is { } ay ? position.Y - ay - o.Y : _shift.Y, z is { } az ? position.Z - az - o.Z : _shift.Z);
        _known = false;
    }

    /// <summary>G92.1/G92.2: the G92 shift is gone.</summary>
    internal void ClearShift()
    {
        _shift = default;
        _known = false;
    }

    /// <summary>The work offsets G10 changed, by key (540 for G54, 5410 + P for the extended ones), in key order.</summary>
    public IEnumerable<int> ChangedOffsets => _set is null ? [] : _set.Keys.Order();

    /// <summary>The tools (H numbers) whose length or wear G10 changed, in order.</summary>
    public IEnumerable<int> ChangedTools => (_tools?.Keys ?? Enumerable.Empty<int>()).Concat(_wear?.Keys ?? Enumerable.Empty<int>()).Distinct().Order();

    /// <summary>The work offset <paramref name="key"/> stands for now (540 for G54, 5410 + P for the extended ones).</summary>
    public Point3 OffsetOf(int key) => Offset(key);

    /// <summary>FANUC's external work offset (G10 L2 P0 where the profile has one), added to every work offset.</summary>
    public Point3 External => _external;

    /// <summary>The G52 local shift.</summary>
    public Point3 Local => _local;

    /// <summary>The G92 shift.</summary>
    public Point3 Shift => _shift;

    /// <summary>The tool length applied on Z now (+ for G43, - for G44, 0 for G49).</summary>
    public double ToolLength
    {
        get => _toolLength;
        internal set
        {
            if (value != _toolLength)
            {
                _toolLength = value;
                _known = false;
            }
        }
    }

    /// <summary>The length of tool <paramref name="h"/> (geometry plus wear): G10's values, else the profile's tool table.</summary>
    public double LengthOf(int h) =>
        (_tools != null && _tools.TryGetValue(h, out var v) ? v : _profile.ToolLength(h)) + (_wear != null && _wear.TryGetValue(h, out var w) ? w : 0);

    /// <summary>G10 L1 / L10 (FANUC geometry): tool <paramref name="h"/>'s length; L11 (FANUC wear) with <paramref name="wear"/>.</summary>
    internal void SetToolLength(int h, double length, bool wear)
    {
        if (wear)
        {
            (_wear ??= new())[h] = length;
        }
        else
        {
            (_tools ??= new())[h] = length;
        }
    }

    private Point3 Offset(int key) =>
        _set != null && _set.TryGetValue(key, out var v) ? v : key % 10 == 0 && key < 600 ? _profile.WorkOffset(key / 10) : default;
}
