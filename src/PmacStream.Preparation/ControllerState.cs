using System.Globalization;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// The library's data blocks for what the controller holds beyond the rotary buffer (its work offset and tool tables,
/// the G52 and G92 shifts), in millimetres: what a G10 sends, and what a start from a block restores.
/// </summary>
internal static class ControllerState
{
    /// <summary>FANUC's external work offset: index 0 of the library's table, which its displacement adds to every offset.</summary>
    public static string ExternalOffset(Point3 e) => $"G10 L2 P0 X{Num(e.X)} Y{Num(e.Y)} Z{Num(e.Z)}";

    /// <summary>Work offset <paramref name="key"/> (540 for G54, 5410 + P for the extended ones) at its table index.</summary>
    public static string WorkOffset(int key, Point3 o) =>
        $"G10 L2 P{HostConversion.WorkOffsetIndex(key).ToString(CultureInfo.InvariantCulture)} X{Num(o.X)} Y{Num(o.Y)} Z{Num(o.Z)}";

    /// <summary>The length of tool <paramref name="h"/> (geometry plus wear).</summary>
    public static string ToolLength(int h, double length) => $"G10 L1 P{h.ToString(CultureInfo.InvariantCulture)} Z{Num(length)}";

    /// <summary>
    /// What the controller must hold to go on at the interpreter's state: the power-on state, then the table values the
    /// program's G10 changed (work offsets, FANUC's external offset, tool lengths) and the G52 and G92 shifts (Before,
    /// sent before the modal preamble), and the selection of a work offset the modal preamble cannot name (G54.1 P,
    /// G59.1-G59.3; Selection, sent after it). A start from a block skips the blocks that set them, and the controller
    /// may hold another job's.
    /// </summary>
    public static (IReadOnlyList<string> Before, string? Selection) Of(Interpreter interp) => Of(interp.Coordinates, interp.Profile);

    /// <summary><see cref="Of(Interpreter)"/> from the tables a block left (<see cref="CanonBlock.Tables"/>), under <paramref name="profile"/>.</summary>
    public static (IReadOnlyList<string> Before, string? Selection) Of(WorkCoordinates coords, MachineProfile profile)
    {
        var lines = new List<string> { HostConversion.PowerOnState };
        if (profile.ExternalWorkOffset && coords.External != default)
        {
            lines.Add(ExternalOffset(coords.External));
        }

        foreach (var key in coords.ChangedOffsets)
        {
            lines.Add(WorkOffset(key, coords.OffsetOf(key)));
        }

        foreach (var h in coords.ChangedTools)
        {
            lines.Add(ToolLength(h, coords.LengthOf(h)));
        }

        if (coords.Local is var l && l != default)
        {
            lines.Add($"G52 X{Num(l.X)} Y{Num(l.Y)} Z{Num(l.Z)}");
        }

        if (coords.Shift is var g && g != default)
        {
            lines.Add($"G92 X{Num(g.X)} Y{Num(g.Y)} Z{Num(g.Z)}");
        }

        var selected = coords.Selected;
        var selection = selected switch
        {
            >= 5410 => "G54.1 P" + (selected - 5410).ToString(CultureInfo.InvariantCulture),
            591 or 592 or 593 => "G59." + (selected - 590).ToString(CultureInfo.InvariantCulture),
            _ => null,
        };
        return (lines, selection);
    }

    private static string Num(double v) => HostConversion.Num(v);
}
