using System.Text;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Jobs;

public class RunSettingsTests
{
    private static RunSettings Read(string json, RunSettings? over = null) =>
        RunSettingsFile.Read(over ?? RunSettings.Default, Encoding.UTF8.GetBytes(json), "settings.json");

    private static string Error(string json)
    {
        var act = () => Read(json);
        return act.Should().Throw<RunSettingsException>().Which.Message;
    }

    [Fact]
    public void One_set_of_defaults_feeds_the_split_and_the_session()
    {
        var d = RunSettings.Default;
        var split = new SplitOptions();
        var session = new StreamingOptions();
        (d.BlocksPerChunk, d.ChunkWords, d.TrackVariable, d.FeedVariable).Should().Be((split.BlocksPerChunk, split.RotWords, split.TrackVariable, split.FeedVariable));
        (d.BufferWords, d.WindowStart, d.WindowEnd, d.TickPeriod).Should().Be((session.BufferWords, session.WindowStart, session.WindowEnd, session.TickPeriod));
        (d.BlocksPerChunk, d.BufferWords, d.WindowStart, d.WindowEnd).Should().Be((1000, 16_000, 0.6, 0.7), "the paper's 1000-line chunks and lines 600-700");
        d.Validate();
    }

    [Fact]
    public void The_session_options_carry_the_settings_and_a_stepped_clock_scales_the_tick()
    {
        var s = RunSettings.Default with { BufferWords = 20_000, WindowStart = 0.5, WindowEnd = 0.8, TickPeriod = TimeSpan.FromMilliseconds(40) };
        var o = s.ToStreamingOptions(StrategyKind.Adaptive, singleBlock: true, defineBuffer: true, clockFactor: 60);
        (o.Strategy, o.BufferWords, o.WindowStart, o.WindowEnd, o.SingleBlock, o.DefineBuffer).Should().Be((StrategyKind.Adaptive, 20_000, 0.5, 0.8, true, true));
        o.TickPeriod.Should().Be(TimeSpan.FromMilliseconds(40 * 60), "the session reasons in the simulator's virtual time");
    }

    [Fact]
    public void A_settings_file_overrides_only_what_it_names_and_round_trips()
    {
        var s = Read("""
            // comments are allowed
            { "linesPerChunk": 500, "windowStart": 0.55, "windowEnd": 0.75, "tickMs": 20, "safeZMode": "highest", }
            """);
        s.Should().Be(RunSettings.Default with { BlocksPerChunk = 500, WindowStart = 0.55, WindowEnd = 0.75, TickPeriod = TimeSpan.FromMilliseconds(20), SafeZMode = SafeZMode.HighestSoFar });

        var all = RunSettings.Default with { BufferWords = 30_000, ChunkWords = 9000, TrackVariable = "M7", FeedVariable = "Q20", SafeZ = 25, Clearance = 2.5 };
        Read(RunSettingsFile.ToJson(all)).Should().Be(all);
    }

    [Theory]
    [InlineData("{\n  \"linesPerChunk\": 500,\n  \"lines\": 7\n}", "settings.json:3:3: error R002: unknown setting 'lines'")]
    [InlineData("{\n  \"bufferWords\": 0\n}", "settings.json:2:18: error R003: bufferWords: must be 1 or more")]
    [InlineData("{ \"windowStart\": \"sixty\" }", "settings.json:1:18: error R003: windowStart: expected a number, got string")]
    [InlineData("{ \"safeZMode\": \"low\" }", "settings.json:1:16: error R003: safeZMode: expected fixed or highest")]
    [InlineData("[1]", "settings.json:1:1: error R001: expected a JSON object")]
    [InlineData("{ \"linesPerChunk\": 500", "settings.json:1:")]
    [InlineData("{ \"windowStart\": 0.8, \"windowEnd\": 0.7 }", "settings.json:1:1: error R003: download window 0.8-0.7")]
    [InlineData("{ \"chunkWords\": 20000 }", "settings.json:1:1: error R003: a chunk of 20000 words does not fit a rotary buffer of 16000 words")]
    [InlineData("{ \"trackVariable\": \"P5\" }", "settings.json:1:20: error R003: track variable must be an M-variable")]
    [InlineData("{ \"blocksPerChunk\": 0 }", "settings.json:1:21: error R003: blocks per chunk must be at least 1")]
    [InlineData("{ \"tracking\": \"sideways\" }", "settings.json:1:15: error R003: tracking: expected \"exact\" or \"paper\", got string")]
    [InlineData("{ \"feed\": 7 }", "settings.json:1:11: error R003: tracking must be exact or paper and feed paper or override")]
    public void A_bad_settings_file_is_reported_with_file_line_column_and_code(string json, string expected)
    {
        Error(json).Should().StartWith(expected);
    }

    [Fact]
    public void The_old_name_linesPerChunk_still_works_with_a_warning_and_blocksPerChunk_without()
    {
        var warnings = new List<string>();
        RunSettingsFile.Read(RunSettings.Default, Encoding.UTF8.GetBytes("{\n  \"linesPerChunk\": 400\n}"), "s.json", warnings.Add)
            .BlocksPerChunk.Should().Be(400);
        warnings.Should().ContainSingle().Which.Should().StartWith("s.json:2:3: warning R004: 'linesPerChunk' is now 'blocksPerChunk'");

        warnings.Clear();
        RunSettingsFile.Read(RunSettings.Default, Encoding.UTF8.GetBytes("{ \"blocksPerChunk\": 400 }"), "s.json", warnings.Add)
            .BlocksPerChunk.Should().Be(400);
        warnings.Should().BeEmpty();
    }

    [Fact]
    public void Every_property_of_the_chunk_shape_is_a_setting_by_its_own_json_name()
    {
        var s = Read("""{ "tracking": "paper", "feed": "override", "wordsPerBlock": 5, "bytesPerWord": 7, "programTail": "M03 M05", "keepN": true, "blockDelete": false, "trackVariable": "m9" }""");
        s.Shape.Should().Be(ChunkShape.Default with
        {
            Tracking = TrackingPlacement.Paper, Feed = FeedMode.Override, WordsPerBlock = 5, BytesPerWord = 7, ProgramTail = "M03 M05", KeepN = true, BlockDelete = false, TrackVariable = "M9",
        });
        Read(RunSettingsFile.ToJson(s)).Should().Be(s, "the file writes the whole shape and reads it back");
        Error("{ \"lines\": 1 }").Should().Contain("known: bufferWords").And.Contain("blocksPerChunk").And.Contain("programTail");
    }

    [Fact]
    public void A_job_record_keeps_the_settings_without_the_shape_which_its_manifest_keeps()
    {
        var s = RunSettings.Default with { BlocksPerChunk = 300, WindowStart = 0.5 };
        var record = RunSettingsFile.ToJson(s, withShape: false);
        record.Should().NotContain("blocksPerChunk").And.NotContain("trackVariable").And.Contain("windowStart");
        Read(record).Should().Be(s with { Shape = ChunkShape.Default });
        Read("""{ "linesPerChunk": 300, "chunkWords": 5000, "windowStart": 0.5 }""").Should().Be(s with { ChunkWords = 5000 }, "a record of an older version, with the shape in its settings, still reads");
    }

    [Fact]
    public void A_named_settings_file_that_is_missing_is_an_io_error()
    {
        var act = () => RunSettingsFile.Load(Path.Combine(Path.GetTempPath(), Guid.NewGuid().ToString("N"), "none.json"));
        act.Should().Throw<FileNotFoundException>().WithMessage("*no such settings file*");
    }

    [Theory]
    [InlineData("0.6-0.7", 0.6, 0.7)]
    [InlineData(" 0.5 - 0.9 ", 0.5, 0.9)]
    [InlineData("60-70%", 0.6, 0.7)]
    public void Windows_parse_as_fractions_or_percent(string text, double start, double end)
    {
        RunSettings.ParseWindow(text).Should().Be((start, end));
    }

    [Theory]
    [InlineData("0.6")]
    [InlineData("a-b")]
    [InlineData("0.6-0.7-0.8")]
    public void A_malformed_window_is_refused_with_the_forms_that_work(string text)
    {
        var act = () => RunSettings.ParseWindow(text);
        act.Should().Throw<FormatException>().WithMessage("*0.6-0.7*60-70%*");
    }
}
