using System.CommandLine;
using PmacStream.Preparation;

namespace PmacStream.Cli.Commands;

/// <summary>
/// The options that shape the chunks (<see cref="ChunkShape"/>), the same for <c>split</c> and <c>stream</c>: each
/// given one overrides the shape of the run settings (the settings file's, else the defaults), and the shape checks
/// itself. <c>--lines</c> is the old name of <c>--blocks-per-chunk</c>, still taken, with a warning.
/// </summary>
internal sealed class ChunkShapeOptions
{
    private static readonly ChunkShape D = ChunkShape.Default;

    private readonly Option<int?> _blocks = new("--blocks-per-chunk") { Description = $"Most source blocks per chunk (default {D.BlocksPerChunk})." };
    private readonly Option<int?> _lines = new("--lines") { Description = "Old name of --blocks-per-chunk (it counts blocks, not text lines)." };
    private readonly Option<int?> _chunkWords = new("--rot-words") { Description = $"Rotary-buffer words a chunk must fit (byte budget = words x --bytes-per-word; default {D.ChunkWords})." };
    private readonly Option<int?> _wordsPerBlock = new("--words-per-block") { Description = $"Words charged at least per block (estimate; default {D.WordsPerBlock})." };
    private readonly Option<int?> _bytesPerWord = new("--bytes-per-word") { Description = $"Text bytes allowed per rotary word (default {D.BytesPerWord})." };
    private readonly Option<string?> _trackVariable = new("--track-var") { Description = $"M-variable receiving the executing source line (default {D.TrackVariable})." };
    private readonly Option<string?> _tracking = new("--tracking") { Description = "exact: M0==line before the move (M0 = executing line; the default); paper: after it, as the paper does." };
    private readonly Option<string?> _feed = new("--feed") { Description = "paper: F(P500) on moves, programmed F carried into P500 (the default); override: keep F words." };
    private readonly Option<string?> _feedVariable = new("--feed-var") { Description = $"Variable the feed expression reads (default {D.FeedVariable})." };
    private readonly Option<string?> _tail = new("--tail") { Description = "Program tail appended to the last chunk (default: the profile's, M05; the paper's machine: \"M03 M05\")." };
    private readonly Option<bool> _keepN = new("--keep-n") { Description = "Keep N numbers (a PMAC reads them as labels)." };
    private readonly Option<bool> _noBlockDelete = new("--no-block-delete") { Description = "Block delete off: emit / blocks instead of skipping them." };

    private ChunkShapeOptions()
    {
        _tracking.AcceptOnlyFromAmong("exact", "paper");
        _feed.AcceptOnlyFromAmong("paper", "override");
    }

    /// <summary>Adds the chunk shape's options to <paramref name="cmd"/>.</summary>
    public static ChunkShapeOptions AddTo(Command cmd)
    {
        var o = new ChunkShapeOptions();
        foreach (var option in new Option[] { o._blocks, o._lines, o._chunkWords, o._wordsPerBlock, o._bytesPerWord, o._trackVariable, o._tracking, o._feed, o._feedVariable, o._tail, o._keepN, o._noBlockDelete })
        {
            cmd.Options.Add(option);
        }

        return o;
    }

    /// <summary><paramref name="shape"/> with the options given on the command line; a shape that cannot work is a usage error.</summary>
    public ChunkShape Apply(ParseResult parse, ChunkShape shape)
    {
        var s = shape;
        if (parse.GetValue(_lines) is { } lines)
        {
            CliConsole.Of(parse).Error.WriteLine("pmacstream: warning: --lines is now --blocks-per-chunk (it counts blocks, not text lines); the old name still works");
            s = s with { BlocksPerChunk = lines };
        }

        s = parse.GetValue(_blocks) is { } blocks ? s with { BlocksPerChunk = blocks } : s;
        s = parse.GetValue(_chunkWords) is { } words ? s with { ChunkWords = words } : s;
        s = parse.GetValue(_wordsPerBlock) is { } perBlock ? s with { WordsPerBlock = perBlock } : s;
        s = parse.GetValue(_bytesPerWord) is { } perWord ? s with { BytesPerWord = perWord } : s;
        s = parse.GetValue(_trackVariable) is { } track ? s with { TrackVariable = track } : s;
        s = parse.GetValue(_tracking) is { } tracking ? s with { Tracking = tracking == "paper" ? TrackingPlacement.Paper : TrackingPlacement.Exact } : s;
        s = parse.GetValue(_feed) is { } feed ? s with { Feed = feed == "override" ? FeedMode.Override : FeedMode.Paper } : s;
        s = parse.GetValue(_feedVariable) is { } feedVariable ? s with { FeedVariable = feedVariable } : s;
        s = parse.GetValue(_tail) is { } tail ? s with { ProgramTail = tail } : s;
        s = parse.GetValue(_keepN) ? s with { KeepN = true } : s;
        s = parse.GetValue(_noBlockDelete) ? s with { BlockDelete = false } : s;
        try
        {
            s.Validate();
        }
        catch (ArgumentException e)
        {
            throw new CliException(e.Message, CliGlobals.UsageOrIo);
        }

        return s;
    }
}
