using System.Text;
using System.Text.Json;
using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>The one record of what shapes a chunk's bytes: validated once, kept whole in the manifest, compared whole by the split cache.</summary>
public sealed class ChunkShapeTests : IDisposable
{
    private readonly TempProgram _program = new(Program(60));

    public void Dispose() => _program.Dispose();

    private static string Program(int moves) =>
        "G21 G90\n" + string.Concat(Enumerable.Range(1, moves).Select(i => $"G01 X{i} Y{i % 7} F800\n")) + "M30\n";

    /// <summary>One shape per property, each differing from the default in that property only.</summary>
    public static TheoryData<string, ChunkShape> OneChangeEach() => new()
    {
        { "blocksPerChunk", ChunkShape.Default with { BlocksPerChunk = 20 } },
        { "chunkWords", ChunkShape.Default with { ChunkWords = 5000 } },
        { "wordsPerBlock", ChunkShape.Default with { WordsPerBlock = 5 } },
        { "bytesPerWord", ChunkShape.Default with { BytesPerWord = 7 } },
        { "trackVariable", ChunkShape.Default with { TrackVariable = "M7" } },
        { "tracking", ChunkShape.Default with { Tracking = TrackingPlacement.Paper } },
        { "feed", ChunkShape.Default with { Feed = FeedMode.Override } },
        { "feedVariable", ChunkShape.Default with { FeedVariable = "Q20" } },
        { "programTail", ChunkShape.Default with { ProgramTail = "M03 M05" } },
        { "keepN", ChunkShape.Default with { KeepN = true } },
        { "blockDelete", ChunkShape.Default with { BlockDelete = false } },
    };

    [Fact]
    public void Every_property_of_the_shape_has_a_case_that_changes_it()
    {
        OneChangeEach().Select(row => (string)row[0]).Should().BeEquivalentTo(ChunkShape.JsonNames, "a new property needs a row here, and nothing else in the cache or the manifest");
    }

    [Theory]
    [MemberData(nameof(OneChangeEach))]
    public void The_split_cache_reuses_a_split_only_for_an_equal_shape(string property, ChunkShape changed)
    {
        var first = Splitter.Split(_program.SourcePath, new SplitOptions());
        var manifest = ChunkManifest.Load(Path.Combine(first.OutputDirectory, ChunkManifest.FileName));
        manifest.Shape.Should().Be(ChunkShape.Default with { ProgramTail = "M05" }, "the manifest keeps the whole shape, its tail named");

        SplitCache.SameOptions(manifest, new SplitOptions()).Should().BeTrue();
        SplitCache.SameOptions(manifest, new SplitOptions { Shape = changed }).Should().BeFalse($"{property} changed");
        SplitCache.TryOpen(_program.SourcePath, first.OutputDirectory, new SplitOptions { Shape = changed }).Should().BeNull($"{property} changed: split again");
        SplitCache.TryOpen(_program.SourcePath, first.OutputDirectory, new SplitOptions()).Should().NotBeNull();
    }

    [Fact]
    public void Variables_compare_without_case_because_the_shape_keeps_them_upper_case()
    {
        (ChunkShape.Default with { TrackVariable = " m0 ", FeedVariable = "p500" }).Should().Be(ChunkShape.Default);
    }

    [Fact]
    public void The_manifest_embeds_the_shape_whole_and_still_writes_the_flat_fields_of_older_versions()
    {
        var shape = ChunkShape.Default with { BlocksPerChunk = 25, Tracking = TrackingPlacement.Paper, ProgramTail = "M03 M05", KeepN = true };
        var result = Splitter.Split(_program.SourcePath, new SplitOptions { Shape = shape });
        var path = Path.Combine(result.OutputDirectory, ChunkManifest.FileName);
        var json = JsonNode.Parse(File.ReadAllText(path))!.AsObject();

        json["shape"]!.AsObject().Select(p => p.Key).Should().Equal(ChunkShape.JsonNames);
        ((int)json["shape"]!["blocksPerChunk"]!, (string)json["shape"]!["tracking"]!).Should().Be((25, "paper"));
        ((int)json["linesPerChunk"]!, (int)json["rotWords"]!, (long)json["maxChunkBytes"]!, (string)json["programTail"]!, (bool)json["keepN"]!)
            .Should().Be((25, 6400, 51_200L, "M03 M05", true), "readers of the older flat fields keep working");
        ChunkManifest.Load(path).Shape.Should().Be(shape);
        result.Manifest.Chunks.Should().OnlyContain(c => c.BlockCount <= 25);
    }

    [Fact]
    public void A_manifest_of_an_older_version_is_read_and_streamed_but_never_reused()
    {
        var result = Splitter.Split(_program.SourcePath, new SplitOptions());
        var path = Path.Combine(result.OutputDirectory, ChunkManifest.FileName);
        var json = JsonNode.Parse(File.ReadAllText(path))!.AsObject();
        json.Remove("shape").Should().BeTrue();
        File.WriteAllText(path, json.ToJsonString());

        var old = ChunkManifest.Load(path);
        old.Shape.Should().BeNull();
        (old.BlocksPerChunk, old.Tracking, old.TrackVariable, old.Chunks.Count).Should().Be((0, TrackingPlacement.Exact, "M0", result.Manifest.Chunks.Count));
        SplitCache.SameOptions(old, new SplitOptions()).Should().BeFalse();
        SplitCache.TryOpen(_program.SourcePath, result.OutputDirectory, new SplitOptions()).Should().BeNull("an old split is split again, not refused");
        PmacStream.Streaming.ChunkedProgram.Open(result.OutputDirectory).TotalChunks.Should().Be(result.Manifest.Chunks.Count, "and it can still be streamed");
    }

    [Theory]
    [InlineData("blocksPerChunk", "0", "blocks per chunk must be at least 1")]
    [InlineData("chunkWords", "0", "chunk words, words per block and bytes per word must be positive")]
    [InlineData("bytesPerWord", "-1", "chunk words, words per block and bytes per word must be positive")]
    [InlineData("trackVariable", "\"P5\"", "track variable must be an M-variable")]
    [InlineData("feedVariable", "\"X1\"", "feed variable must be a P, Q or M variable")]
    [InlineData("programTail", "\"M05\\u0001\"", "program tail must be plain ASCII")]
    public void One_place_checks_a_shape_whoever_asks(string property, string value, string message)
    {
        var shape = ChunkShape.Default.WithJson(property, JsonDocument.Parse(value).RootElement)!;
        shape.Invoking(s => s.Validate()).Should().Throw<ArgumentException>().WithMessage(message + "*");
        new SplitOptions { Shape = shape }.Invoking(o => o.Validate()).Should().Throw<ArgumentException>().WithMessage(message + "*", "the splitter's check is the shape's");
        (RunSettings.Default with { Shape = shape }).Invoking(s => s.Validate()).Should().Throw<ArgumentException>().WithMessage(message + "*", "so is the run settings'");
        var file = () => RunSettingsFile.Read(RunSettings.Default, Encoding.UTF8.GetBytes($"{{ \"{property}\": {value} }}"), "s.json");
        file.Should().Throw<RunSettingsException>().WithMessage($"s.json:1:*: error R003: {message}*", "and the settings file's");
    }

    [Fact]
    public void The_run_settings_split_with_their_shape_and_the_profiles_tail_when_the_shape_leaves_it_open()
    {
        var paper = MachineProfile.Parse(MachineProfile.Default.ToJson().Replace("\"programTail\": \"M05\"", "\"programTail\": \"M03 M05\"", StringComparison.Ordinal), "paper.json");
        var settings = RunSettings.Default with { Shape = ChunkShape.Default with { BlocksPerChunk = 300, Feed = FeedMode.Override } };
        var options = settings.ToSplitOptions(paper, outDir: null, force: false);
        options.ResolvedShape.Should().Be(settings.Shape with { ProgramTail = "M03 M05" });
        (settings with { Shape = settings.Shape with { ProgramTail = "M30" } }).ToSplitOptions(paper, null, false).ProgramTail.Should().Be("M30", "a tail of its own wins");
    }
}
