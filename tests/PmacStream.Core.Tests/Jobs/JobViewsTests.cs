using PmacStream.Core.Tests.Preparation;
using PmacStream.Jobs;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Jobs;

/// <summary>The views the job service gives a screen instead of preparation's and streaming's types (what the HMI reads).</summary>
public sealed class JobViewsTests : IDisposable
{
    private readonly TempProgram _program = new(Program(2500));
    private readonly TestFolder _temp = new("views");
    private readonly JobService _service;

    public JobViewsTests() => _service = new(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });

    public void Dispose()
    {
        _program.Dispose();
        _temp.Dispose();
    }

    private static string Program(int moves) => TestPrograms.Text(TestPrograms.Metric + "G01 F1200\n", moves, TestPrograms.Grid(40));

    [Fact]
    public async Task A_split_view_lists_the_manifests_chunks_and_the_rows_that_carry_each_tracked_line()
    {
        var view = await _service.PrepareViewAsync(new PrepareRequest(_program.SourcePath, RunSettings.Default));

        var split = ChunkedProgram.Open(view.Folder);
        view.Chunks.Select(c => (c.Number, c.FileName, c.FirstSourceLine, c.LastSourceLine, c.BlockCount))
            .Should().Equal(split.Manifest.Chunks.Select(c => (c.Index, c.FileName, c.FirstSourceLine, c.LastSourceLine, c.BlockCount)));
        view.Chunks.Should().HaveCount(3);
        view.TotalBlocks.Should().Be(split.Manifest.TotalBlocks);
        view.SourcePath.Should().Be(Path.GetFullPath(_program.SourcePath));

        var rows = _service.RowsOf(view, 2);
        rows.TrackedLines.Should().NotBeEmpty().And.BeInAscendingOrder();
        rows.TrackedLines.Should().HaveSameCount(rows.FileLines);
        var file = File.ReadAllLines(view.ChunkPath(view.Chunks[1]));
        for (var i = 0; i < rows.TrackedLines.Count; i += 97)
        {
            file[rows.FileLines[i] - 1].Should().Contain($"M0=={rows.TrackedLines[i]}", "the row shown as executing carries the block's synchronous assignment");
        }
    }

    [Fact]
    public async Task A_view_made_elsewhere_is_read_from_its_folder_and_plans_the_same_preamble()
    {
        var view = await _service.PrepareViewAsync(new PrepareRequest(_program.SourcePath, RunSettings.Default));
        var elsewhere = new SplitView(view.SourcePath, view.Folder, [], 0);

        var preamble = _service.PreambleOf(view, 1200, RunSettings.Default);

        preamble.Should().NotBeEmpty();
        _service.PreambleOf(elsewhere, 1200, RunSettings.Default).Should().Equal(preamble);
        _service.RowsOf(elsewhere, 3).Should().BeEquivalentTo(_service.RowsOf(view, 3));
    }

    [Fact]
    public void No_interrupted_job_without_a_job_store_gives_no_view()
    {
        _service.FindInterruptedView(_program.SourcePath).Should().BeNull();
        File.Exists(_service.JobDatabase).Should().BeFalse("looking does not create a job store");
    }
}
