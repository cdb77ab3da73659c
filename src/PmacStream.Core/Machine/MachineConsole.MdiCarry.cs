using System.Globalization;
using PmacStream.GCode;

namespace PmacStream.Machine;

/// <summary>
/// What an MDI call carries besides the modal codes: where the axes stand and the G52/G92 shifts (the library starts
/// every program in its power-on state, so they are written again), and the canned cycle in force with its words.
/// </summary>
public sealed partial class MachineConsole
{
    /// <summary>
    /// The MDI program's first lines: the carried modal state; a rapid to where the axes stand (it moves nothing: the
    /// position is the controller's, in the program coordinates the controller will apply, so the interpreter starts
    /// where the machine is and computes cycles, G92 and G28 from there); the G52 and G92 shifts the controller held
    /// (the library's Q-variables), set again; the modal state once more (distance and motion mode after the rapid).
    /// </summary>
    private async Task<IReadOnlyList<string>> HeaderAsync(CarriedMdiState carried, CancellationToken cancellationToken)
    {
        var lines = new List<string> { carried.Line };
        var map = new Preparation.LibraryMap();
        if (await WorkPositionAsync(Connection, Options.Axes, map, Options.CoordinateSystem, cancellationToken).ConfigureAwait(false) is not { } work)
        {
            return lines; // no X, Y, Z axes: the interpreter starts where it always did
        }

        var q = Numbers(await Connection.GetResponseAsync(
            $"{Cs} {map.Q(1)} {map.Q(2)} {map.Q(3)} {map.Q(4)} {map.Q(5)} {map.Q(6)}", cancellationToken).ConfigureAwait(false));
        double Q(int i) => i < q.Count ? q[i] : 0;
        var local = new Point3(Q(0), Q(1), Q(2));
        var shift = new Point3(Q(3), Q(4), Q(5));
        var unit = carried.Line.Contains("G20", StringComparison.Ordinal) ? 25.4 : 1.0;
        string Axes(Point3 p) => string.Create(CultureInfo.InvariantCulture, $"X{p.X / unit:0.######} Y{p.Y / unit:0.######} Z{p.Z / unit:0.######}");

        // Before the shifts: the program position of where the axes stand is the work position plus both shifts.
        lines.Add("G90 G00 " + Axes(work + local + shift));
        if (local != default)
        {
            lines.Add("G52 " + Axes(local));
        }

        if (shift != default)
        {
            lines.Add("G92 " + Axes(work)); // the position reads as it did: the same shift, for the host and the library
        }

        lines.Add(carried.Line);
        return lines;
    }

    /// <summary>
    /// The canned cycle in force after each block, with the words it keeps as the program wrote them (FANUC keeps R, Z,
    /// Q and P from block to block until G80 or a motion code; in G91 they stay increments, as written).
    /// </summary>
    private sealed class CycleWords
    {
        private readonly SortedDictionary<char, string> _words = [];
        private string? _code;

        /// <summary>The cycle and its words (<c>G81 R2 Z-5</c>), or null when none is in force.</summary>
        public string? Text => _code is null ? null : string.Join(' ', new[] { _code }.Concat(_words.Select(w => w.Key + w.Value)));

        public void After(GBlock block, ModalState state)
        {
            if (state.Cycle is not { } cycle)
            {
                _code = null;
                _words.Clear();
                return;
            }

            _code = "G" + cycle.ToString("0.#", CultureInfo.InvariantCulture); // another cycle keeps the words (until G80)

            foreach (var w in block.WordList)
            {
                var letter = char.ToUpperInvariant(w.Letter);
                if (letter is 'R' or 'Z' or 'Q' or 'P')
                {
                    _words[letter] = w.Value.ToString("0.######", CultureInfo.InvariantCulture);
                }
            }
        }
    }
}
