using System.Globalization;
using PmacStream.Preparation;

namespace PmacStream.Streaming;

/// <summary>
/// The online commands to one coordinate system as a Turbo PMAC reads them (<c>&amp;1 R</c>, <c>&amp;1 H</c>,
/// <c>&amp;1 B0</c>, <c>&amp;1??</c> ...), and the live feed: the feed variable in paper mode (<c>P500=800</c>), the
/// <c>%</c> override otherwise. Written in one place, so the start, the queries and the operator commands agree.
/// </summary>
internal sealed class CoordinateSystemCommands
{
    /// <summary>Commands to coordinate system <paramref name="number"/>, the feed in <paramref name="feedMode"/> through <paramref name="feedVariable"/> (blank: <c>P500</c>).</summary>
    public CoordinateSystemCommands(int number, FeedMode feedMode, string? feedVariable)
    {
        Prefix = "&" + number.ToString(CultureInfo.InvariantCulture);
        FeedMode = feedMode;
        FeedVariable = string.IsNullOrWhiteSpace(feedVariable) ? "P500" : feedVariable.Trim();
    }

    /// <summary>The addressing prefix, <c>&amp;1</c>.</summary>
    public string Prefix { get; }

    /// <summary>How the live feed is set.</summary>
    public FeedMode FeedMode { get; }

    /// <summary>The variable <c>F(P500)</c> reads in paper mode.</summary>
    public string FeedVariable { get; }

    /// <summary>Runs one block (<c>&amp;n S</c>).</summary>
    public string Step => $"{Prefix} S";

    /// <summary>Feed hold (<c>&amp;n H</c>).</summary>
    public string Hold => $"{Prefix} H";

    /// <summary>Abort (<c>&amp;n A</c>).</summary>
    public string Abort => $"{Prefix} A";

    /// <summary>Points the coordinate system at its rotary buffer (<c>&amp;n B0</c>).</summary>
    public string PointAtRotary => $"{Prefix} B0";

    /// <summary>Deletes the rotary buffer (<c>&amp;n DELETE ROT</c>).</summary>
    public string DeleteRotary => $"{Prefix} DELETE ROT";

    /// <summary>The status query (<c>&amp;n??</c>).</summary>
    public string Status => $"{Prefix}??";

    /// <summary>Reads the live feed: the feed variable, or the override (<c>&amp;n %</c>).</summary>
    public string ReadFeed => FeedMode == FeedMode.Paper ? FeedVariable : $"{Prefix} %";

    /// <summary>Starts or continues: <c>&amp;n R</c>, or <see cref="Step"/> in single-block mode.</summary>
    public string Run(bool singleBlock) => singleBlock ? Step : $"{Prefix} R";

    /// <summary>Defines the rotary buffer with <paramref name="words"/> words.</summary>
    public string DefineRotary(int words) => $"{Prefix} DEFINE ROT {words.ToString(CultureInfo.InvariantCulture)}";

    /// <summary>Sets the live feed (<paramref name="shown"/> is the value as sent, at most 3 decimals).</summary>
    public string SetFeed(double value, out string shown)
    {
        shown = value.ToString("0.###", CultureInfo.InvariantCulture);
        return FeedMode == FeedMode.Paper ? $"{FeedVariable}={shown}" : $"{Prefix} %{shown}";
    }
}
