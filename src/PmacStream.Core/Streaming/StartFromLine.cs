using System.Globalization;
using System.Text.RegularExpressions;
using PmacStream.GCode;
using PmacStream.Program;

namespace PmacStream.Streaming;

/// <summary>What starting at a block needs: the state before it, where it starts, and the preamble to get there safely.</summary>
/// <param name="Line">The source line of the block started at (the first motion block at or after the requested line).</param>
/// <param name="State">Modal state in force before that block (units, plane, distance mode, work offset, tool, length offset, spindle, coolant, feed).</param>
/// <param name="Start">Where the block starts (the end of the move before it), program coordinates.</param>
/// <param name="GCode">The preamble as G-code, for showing to the operator.</param>
/// <param name="PmacLines">The preamble as rotary-buffer lines (feed through the feed variable in paper mode).</param>
public sealed record StartPlan(int Line, ModalState State, Point3 Start, IReadOnlyList<string> GCode, IReadOnlyList<string> PmacLines);

/// <summary>
/// "Start from any block" (the paper's HMI feature, and resume after an abort): replays the source through the
/// interpreter up to the block, then builds a preamble that restores the modal state and approaches safely:
/// retract to a safe Z, rapid in XY to the block's start, feed down to its Z, then the distance mode, motion mode and feed.
/// </summary>
public static class StartFromLine
{
    private static readonly Regex FWord = new(@"(?<![A-Z])F\s*([-+]?[\d.]+)", RegexOptions.IgnoreCase | RegexOptions.CultureInvariant);
    private static readonly Regex AxisWord = new(@"(?<![A-Z])[XYZ]\s*[-+]?[\d.]", RegexOptions.IgnoreCase | RegexOptions.CultureInvariant);

    /// <summary>Plans a start at the first motion block at or after <paramref name="line"/>.</summary>
    /// <param name="sourcePath">The G-code source.</param>
    /// <param name="line">Requested source line.</param>
    /// <param name="safeZ">Safe height to retract to before moving in XY (program coordinates).</param>
    /// <param name="feedMode">How feed reaches the controller (paper: <c>P500=</c> plus <c>F(P500)</c> on moves).</param>
    /// <param name="feedVariable">The feed variable (P500).</param>
    /// <param name="profile">Machine profile for the interpreter (default: the seed-002 mill).</param>
    /// <exception cref="ArgumentOutOfRangeException">No motion block at or after the line.</exception>
    public static StartPlan Plan(string sourcePath, int line, double safeZ = 10, FeedMode feedMode = FeedMode.Paper, string feedVariable = "P500", MachineProfile? profile = null)
    {
        var interp = new Interpreter(profile ?? MachineProfile.Default);
        using var reader = GCodeReader.Open(sourcePath);
        while (reader.Read())
        {
            var block = reader.Current;
            if (block.LineNumber >= line)
            {
                // State and position before this block: peek at what it does without losing the "before".
                var before = interp.State;
                var start = interp.Position;
                var decoded = interp.Step(block);
                if (decoded is not null && decoded.Motion != MotionKind.None)
                {
                    return Build(block.LineNumber, before, start, safeZ, feedMode, feedVariable);
                }

                continue;
            }

            interp.Step(block);
        }

        throw new ArgumentOutOfRangeException(nameof(line), $"{sourcePath}: no motion block at or after line {line}");
    }

    /// <summary>Builds the preamble for a known state and start point.</summary>
    public static StartPlan Build(int line, ModalState state, Point3 start, double safeZ, FeedMode feedMode = FeedMode.Paper, string feedVariable = "P500")
    {
        var modal = state.ToPreamble().ToList();
        var last = modal[^1];
        modal.RemoveAt(modal.Count - 1);
        var approachFeed = state.Feed is > 0 ? Math.Min(state.Feed.Value, 500) : 300;
        var z = Math.Max(safeZ, start.Z);
        var gcode = new List<string>(modal)
        {
            $"G90 G00 Z{Num(z)}",
            $"G00 X{Num(start.X)} Y{Num(start.Y)}",
            $"G01 Z{Num(start.Z)} F{Num(approachFeed)}",
            last,
        };

        var pmac = new List<string>();
        foreach (var g in gcode)
        {
            pmac.AddRange(ToPmac(g, feedMode, feedVariable));
        }

        return new StartPlan(line, state, start, gcode, pmac);
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

    /// <summary>
    /// Move times of every motion block of a source, from the interpreter (seconds at programmed feed), for the ETA
    /// and the adaptive lead. Returns null for programs above <paramref name="maxBlocks"/> blocks, where the
    /// measured block rate is used instead so memory stays bounded.
    /// </summary>
    public static MoveTimeTable? MoveTimes(string sourcePath, int maxBlocks = 2_000_000, MachineProfile? profile = null)
    {
        var interp = new Interpreter(profile ?? MachineProfile.Default);
        var list = new List<(int, double, double)>();
        using var reader = GCodeReader.Open(sourcePath);
        while (reader.Read())
        {
            var d = interp.Step(reader.Current);
            if (d is not null && d.Motion != MotionKind.None)
            {
                if (list.Count >= maxBlocks)
                {
                    return null;
                }

                list.Add((d.Line, d.DurationSeconds, d.Modal.Feed ?? double.NaN));
            }
        }

        return new MoveTimeTable(list);
    }

    private static string Num(double v) => Math.Round(v, 4).ToString("0.####", CultureInfo.InvariantCulture);
}
