using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// A move under cutter radius compensation as the controller runs it: the interpreter's compensated positions in work
/// coordinates (absolute, whatever the distance mode), the outside corner first (an arc about the programmed corner,
/// or for a rapid a straight way to the arc's end), then the line. The PMAC's own compensation never runs: the host
/// sends where the tool goes, so the controller, the preview and the position proof hold the same positions.
/// </summary>
internal static class CompensatedMoves
{
    /// <summary>
    /// Appends the move's lines; <paramref name="start"/> is the machine position before the block (or, after an
    /// inside corner, <see cref="CanonBlock.AmendedEnd"/>: where the offset paths cross). Returns the index of the line
    /// that ends the move: the line an inside corner at the next move rewrites (<see cref="MoveEndTo"/>).
    /// </summary>
    public static int Write(List<string> lines, in CanonBlock block, Point3 start, double? feed)
    {
        start = block.AmendedEnd ?? start;
        var incremental = !block.Absolute;
        if (incremental)
        {
            lines.Add("G90");
        }

        var offset = block.Offset;
        var rapid = block.MotionCode == 0;
        var f = feed is { } fv ? " F" + HostConversion.Num(fv) : string.Empty;
        if (block.Corner is { } corner)
        {
            var mid = corner.Mid - offset;
            if (corner.Arc)
            {
                // The PMAC's centre vector is incremental from the arc's start (its default INC(R)).
                var centre = corner.Centre - start;
                lines.Add($"{(corner.Clockwise ? "G02" : "G03")} X{HostConversion.Num(mid.X)} Y{HostConversion.Num(mid.Y)} I{HostConversion.Num(centre.X)} J{HostConversion.Num(centre.Y)}{f}");
                f = string.Empty;
            }
            else
            {
                lines.Add($"G00 X{HostConversion.Num(mid.X)} Y{HostConversion.Num(mid.Y)}");
            }
        }

        var end = block.Position - offset;
        var moveLine = lines.Count;
        if (block.MotionCode is 2 or 3 && block.ArcCentre is { } c)
        {
            // The offset arc about the programmed centre, from where the tool is (after the corner, if any).
            var v = c - (block.Corner?.Mid ?? start);
            lines.Add($"{(block.ArcClockwise ? "G02" : "G03")} X{HostConversion.Num(end.X)} Y{HostConversion.Num(end.Y)} Z{HostConversion.Num(end.Z)} I{HostConversion.Num(v.X)} J{HostConversion.Num(v.Y)}{f}");
        }
        else
        {
            lines.Add($"{(rapid ? "G00" : "G01")} X{HostConversion.Num(end.X)} Y{HostConversion.Num(end.Y)} Z{HostConversion.Num(end.Z)}{(rapid ? string.Empty : f)}");
        }
        if (rapid && f.Length > 0)
        {
            lines.Add(f.TrimStart()); // the block's feed, for the feed moves after it
        }

        if (incremental)
        {
            lines.Add("G91");
        }

        return moveLine;
    }

    /// <summary>
    /// A move line <see cref="Write"/> wrote, ending at <paramref name="end"/> (work coordinates) on X and Y instead:
    /// an inside corner moved the end back to where the offset paths cross. The rest of the line (Z, an arc's centre
    /// vector from its start, the feed) stays.
    /// </summary>
    public static string MoveEndTo(string line, Point3 end)
    {
        var words = line.Split(' ');
        for (var i = 0; i < words.Length; i++)
        {
            if (words[i].StartsWith('X'))
            {
                words[i] = "X" + HostConversion.Num(end.X);
            }
            else if (words[i].StartsWith('Y'))
            {
                words[i] = "Y" + HostConversion.Num(end.Y);
            }
        }

        return string.Join(' ', words);
    }
}
