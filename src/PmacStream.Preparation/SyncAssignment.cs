using System.Collections.Concurrent;
using System.Globalization;
using System.Text;
using System.Text.RegularExpressions;

namespace PmacStream.Preparation;

/// <summary>
/// The tracking assignment on every move of a chunk, <c>M0==n</c>: a synchronous assignment, so the M-variable takes
/// the block's source line when the move starts executing, not when the lookahead calculates it, and reading the
/// variable tells the host which block runs. This type is the one place that knows how it is written (variable,
/// operator, placement on the line) and how it is read back: from a chunk line (which lines are tracked, and the line
/// without it for classification) and from the controller (the online read and reset of the variable).
/// </summary>
public sealed class SyncAssignment
{
    /// <summary>The tracking variable when none is configured.</summary>
    public const string DefaultVariable = "M0";

    /// <summary>The synchronous assignment operator (a plain <c>=</c> would take effect at calculation time).</summary>
    public const string Operator = "==";

    // One compiled pattern per variable name: a program is opened many times in a job store's life.
    private static readonly ConcurrentDictionary<string, Regex> Markers = new(StringComparer.OrdinalIgnoreCase);

    private Regex? _marker;

    /// <summary>Creates the assignment of <paramref name="variable"/> (blank: <see cref="DefaultVariable"/>) at <paramref name="placement"/>.</summary>
    public SyncAssignment(string? variable = null, TrackingPlacement placement = TrackingPlacement.Exact)
    {
        Variable = string.IsNullOrWhiteSpace(variable) ? DefaultVariable : variable.Trim();
        Placement = placement;
        Prefix = Variable + Operator;
    }

    /// <summary>The assignment a split program's manifest records.</summary>
    public static SyncAssignment Of(ChunkManifest manifest)
    {
        ArgumentNullException.ThrowIfNull(manifest);
        return new SyncAssignment(manifest.TrackVariable, manifest.Tracking);
    }

    /// <summary>The assignment a split writes with these options.</summary>
    public static SyncAssignment Of(SplitOptions options)
    {
        ArgumentNullException.ThrowIfNull(options);
        return new SyncAssignment(options.TrackVariable, options.Tracking);
    }

    /// <summary>The tracking M-variable (<c>M0</c>).</summary>
    public string Variable { get; }

    /// <summary>Where the assignment stands on a move's line.</summary>
    public TrackingPlacement Placement { get; }

    /// <summary>
    /// True when the variable names the block before the executing one: at the end of the line (paper placement) the
    /// assignment is written when the next move starts.
    /// </summary>
    public bool LagsOneMove => Placement == TrackingPlacement.Paper;

    /// <summary>The text before the line number: <c>M0==</c>.</summary>
    public string Prefix { get; }

    /// <summary>The online command that reads the variable (the executing line).</summary>
    public string ReadCommand => Variable;

    /// <summary>The online command that sets the variable to 0 before a job (a value of an earlier job reads as progress).</summary>
    public string ResetCommand => Variable + "=0";

    /// <summary><see cref="Prefix"/> as the ASCII bytes the splitter writes.</summary>
    public byte[] PrefixBytes() => Encoding.ASCII.GetBytes(Prefix);

    /// <summary>The assignment for source line <paramref name="sourceLine"/>: <c>M0==12</c>.</summary>
    public string Format(int sourceLine) => Prefix + sourceLine.ToString(CultureInfo.InvariantCulture);

    /// <summary>
    /// A move's words with the assignment placed: first (after an <c>N</c> label when there is one) with exact
    /// placement, last with paper placement.
    /// </summary>
    public string Place(string words, int sourceLine, string? label = null)
    {
        var lead = string.IsNullOrEmpty(label) ? string.Empty : label + " ";
        return Placement == TrackingPlacement.Exact
            ? $"{lead}{Format(sourceLine)} {words}"
            : $"{lead}{words} {Format(sourceLine)}";
    }

    // Built when first read: the splitter only writes.
    private Regex Marker => _marker ??= Markers.GetOrAdd(Variable, static v => new Regex(
        $@"(?<![A-Z0-9]){Regex.Escape(v)}\s*==\s*(\d+)",
        RegexOptions.Compiled | RegexOptions.CultureInvariant | RegexOptions.IgnoreCase));

    /// <summary>
    /// Reads the source line a program line tracks (its first assignment; blanks around <c>==</c> allowed, any case);
    /// false, with 0, when the line carries none.
    /// </summary>
    public bool TryRead(string line, out int sourceLine)
    {
        var m = Marker.Match(line);
        sourceLine = m.Success && int.TryParse(m.Groups[1].ValueSpan, NumberStyles.None, CultureInfo.InvariantCulture, out var n) ? n : 0;
        return m.Success;
    }

    /// <summary>The line with every tracking assignment replaced by a blank: what is left to classify (motion or not).</summary>
    public string Without(string line) => Marker.Replace(line, " ");
}
