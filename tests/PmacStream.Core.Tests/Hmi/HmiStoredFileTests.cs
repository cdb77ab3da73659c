using Microsoft.Data.Sqlite;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Sim;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>
/// A file opened in the HMI runs as a stored revision, as <c>stream FILE</c> runs it: its split finds it in the store
/// by SHA-256 or imports it, and its job, start from a line and preview read the revision. Headless, over the real
/// job service on an SQLite store of the test's own and the simulated Turbo PMAC in process.
/// </summary>
public sealed class HmiStoredFileTests : IAsyncLifetime
{
    private readonly TestFolder _temp = new("hmi-stored");
    private readonly PmacSimulator _sim = new(new SimOptions());
    private readonly List<MainPresenter> _presenters = [];
    private string _source = string.Empty;

    private StoreLocation Store => StoreLocation.Sqlite(Path.Combine(_temp.Path, "store.db"));

    public Task InitializeAsync()
    {
        // A short part (two spindle blocks, a plunge, 30 moves): a job runs in a few virtual seconds.
        _source = TestPrograms.Write(Path.Combine(_temp.Path, "part.nc"),
            TestPrograms.Text($"({Guid.NewGuid():N})\nG21 G90 G17 G54\nM03 S1000\nG0 X0 Y0 Z5\nG1 Z-1 F600\n", 30, i => $"G1 X{i} Y{i % 3}"));
        return Task.CompletedTask;
    }

    public async Task DisposeAsync()
    {
        foreach (var p in _presenters)
        {
            await p.DisposeAsync();
        }

        _sim.Dispose();
        _temp.Dispose();
    }

    private (MainPresenter P, FakeView V, JobService Service) NewHmi()
    {
        var service = new JobService(new JobServiceOptions { Simulator = SimRig.BuiltIn(_sim, "hmi", step: false), Store = Store });
        var view = new FakeView();
        var sink = new HmiLogSink();
        var log = new Serilog.LoggerConfiguration().WriteTo.Hmi(sink).CreateLogger().ForContext<MainPresenter>();
        var p = new MainPresenter(view, new CoreHmiBackend(service), sink, log);
        _presenters.Add(p);
        return (p, view, service);
    }

    private static async Task Do(MainPresenter p, Action a)
    {
        a();
        await p.WhenIdleAsync();
    }

    private async Task<(MainPresenter P, FakeView V, JobService Service)> SplitAsync()
    {
        var (p, v, service) = NewHmi();
        await Do(p, () => v.ChooseFile(_source));
        await Do(p, v.ClickConnect);
        await Do(p, v.ClickSplit);
        v.Errors.Should().BeEmpty();
        return (p, v, service);
    }

    private async Task RunToEnd(MainPresenter p)
    {
        for (var i = 0; i < 2_000 && p.JobActive; i++)
        {
            await p.TickAsync();
            _sim.Advance(TimeSpan.FromSeconds(1));
        }

        p.JobActive.Should().BeFalse("the job should have finished");
    }

    [Fact]
    public async Task A_file_opened_twice_is_stored_once_and_its_job_records_that_revision()
    {
        var (p, v, service) = await SplitAsync();
        var id = service.StoredPrograms().Should().ContainSingle().Which.Id;
        v.Log.Should().Contain(l => l.Contains($"(program {id} of the store)"));
        service.PreparationsStored.Should().Be(1, "the split is kept with the revision");

        await Do(p, () => v.ChooseFile(_source));
        await Do(p, v.ClickSplit);
        service.StoredPrograms().Should().ContainSingle("the same bytes under the same profile are found by SHA-256, not imported again")
            .Which.Id.Should().Be(id);
        service.PreparationsReused.Should().Be(1, "the second split is the stored preparation");

        await Do(p, v.ClickExecute);
        await RunToEnd(p);
        v.Errors.Should().BeEmpty();
        v.Status.State.Should().Be("Completed");
        service.JobHistory().Should().ContainSingle().Which.ProgramId.Should().Be(id, "the job names the revision, as stream FILE's does");
    }

    [Fact]
    public async Task A_start_from_a_line_of_a_file_plans_from_the_store_and_shows_the_files_preamble()
    {
        var (p, v, service) = await SplitAsync();
        var id = service.StoredPrograms().Single().Id;
        var from = ChunkedProgram.Open(Splitter.DefaultOutDir(_source)).TrackedLines().ElementAt(20);
        var reinterpreted = service.PlanStart(ChunkedProgram.Open(Splitter.DefaultOutDir(_source)), from, RunSettings.Default with { BlocksPerChunk = v.BlocksPerChunk });

        v.SelectedLine = from;
        await Do(p, v.ClickStartFromLine);
        v.Errors.Should().BeEmpty();
        v.Confirmations.Single().Text.Should().Contain(string.Join(Environment.NewLine, reinterpreted.GCode), "the stored states give the preamble the file gives");
        service.StartsFromStore.Should().Be(2, "the preamble shown and the job's plan both read the store");
        service.StartFallbacks.Should().Be(0);

        await RunToEnd(p);
        v.Status.State.Should().Be("Completed");
        var job = service.JobHistory().Single();
        job.ProgramId.Should().Be(id);
        service.FindJob(job.Id).FromLine.Should().Be(from);
    }

    [Fact]
    public async Task A_job_of_a_file_resumed_after_a_crash_shows_its_preamble_from_the_store_and_the_next_start_names_the_revision()
    {
        // 300 moves of 1 mm at F600 in chunks of 50: the job is still running when the host dies.
        _source = TestPrograms.Write(Path.Combine(_temp.Path, "long.nc"),
            TestPrograms.Text("G21 G90 G17 G54\nM03 S1000\nG0 X0 Y0 Z5\nG1 Z-1 F600\n", 300, i => $"G1 X{i % 50} Y{i / 50}"));
        var (p, v, service) = NewHmi();
        await Do(p, () => v.ChooseFile(_source));
        await Do(p, v.ClickConnect);
        v.BlocksPerChunk = 50;
        await Do(p, v.ClickSplit);
        var id = service.StoredPrograms().Single().Id;
        await Do(p, v.ClickExecute);
        for (var i = 0; i < 200 && v.ExecutingLine < 100; i++)
        {
            await p.TickAsync();
            _sim.Advance(TimeSpan.FromSeconds(0.5));
        }

        v.ExecutingLine.Should().BeGreaterThanOrEqualTo(100);
        _presenters.Remove(p); // the host dies: no abort, no goodbye

        var (p2, v2, service2) = NewHmi();
        await Do(p2, () => v2.ChooseFile(_source));
        await Do(p2, v2.ClickConnect);
        await Do(p2, v2.ClickResumeInterrupted);
        v2.Errors.Should().BeEmpty();
        v2.Confirmations.Should().ContainSingle().Which.Text.Should().Contain("Resume job");
        service2.StartsFromStore.Should().BeGreaterThanOrEqualTo(1, "the preamble shown is planned from the revision the job recorded");
        service2.StartFallbacks.Should().Be(0);
        await RunToEnd(p2);
        v2.Status.State.Should().Be("Completed");

        await Do(p2, v2.ClickExecute);
        await RunToEnd(p2);
        service2.JobHistory().Select(j => j.ProgramId).Should().Equal([id, id], "the resumed program is the revision, as if split here");
        service2.StoredPrograms().Should().ContainSingle();
    }

    [Fact]
    public async Task A_store_that_cannot_import_leaves_the_file_to_run_without_a_revision_and_the_log_says_why()
    {
        using (ProgramStores.Open(Store))
        using (var c = new SqliteConnection($"Data Source={Store.Target};Pooling=False"))
        {
            // The library cannot take a program (a full disk, a role without INSERT on it); the job history still can.
            c.Open();
            using var cmd = c.CreateCommand();
            cmd.CommandText = "CREATE TRIGGER refuse BEFORE INSERT ON programs BEGIN SELECT RAISE(ABORT, 'database or disk is full'); END;";
            cmd.ExecuteNonQuery();
        }

        var (p, v, service) = await SplitAsync();
        v.Log.Should().Contain(l => l.Contains("Not stored, run as a file") && l.Contains("cannot import") && l.Contains("disk is full"));
        v.ChunkFiles.Should().NotBeEmpty("the file is split beside itself, as before the store");
        service.StoredPrograms().Should().BeEmpty();

        await Do(p, v.ClickExecute);
        await RunToEnd(p);
        v.Errors.Should().BeEmpty();
        v.Status.State.Should().Be("Completed");
        service.JobHistory().Should().ContainSingle().Which.ProgramId.Should().BeNull("the job names no revision the store does not hold");
    }

    [Fact]
    public async Task A_file_with_errors_is_stored_with_its_diagnostics_and_still_refused()
    {
        var bad = TestPrograms.Write(Path.Combine(_temp.Path, "bad.nc"), "G21 G90\nG01 X10 Y10 F500\nG00 G01 X20\nM30\n");
        var (p, v, service) = NewHmi();
        await Do(p, () => v.ChooseFile(bad));
        await Do(p, v.ClickConnect);
        await Do(p, v.ClickSplit);

        v.Errors.Should().ContainSingle().Which.Should().Contain("bad.nc:3:");
        v.Diagnostics.Should().Contain(d => d.StartsWith("3:", StringComparison.Ordinal));
        v.ChunkFiles.Should().BeEmpty();
        service.StoredPrograms().Should().ContainSingle().Which.Errors.Should().BeGreaterThan(0, "it is stored with its diagnostics, as stream FILE stores it");
        Directory.Exists(Splitter.DefaultOutDir(bad)).Should().BeFalse("nothing is split");
    }
}
