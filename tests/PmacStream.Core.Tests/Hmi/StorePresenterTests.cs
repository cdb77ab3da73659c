using System.Text;
using PmacStream.GCode;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>
/// The Store page's presenter, headless, over the real job service on an SQLite store: the job history (the same
/// records <c>jobs --json</c> prints) and the program revisions, and Open of a stored revision.
/// </summary>
public sealed class StorePresenterTests : IDisposable
{
    private readonly TestFolder _folder = new("hmi-store");
    private readonly FakeStoreView _view = new();
    private readonly List<(string Path, string? Profile)> _opened = [];
    private readonly List<long> _openedRevisions = [];

    public void Dispose() => _folder.Dispose();

    private sealed class FakeStoreView : IStoreView
    {
        public string StoreLocationText { get; set; } = string.Empty;

        public IReadOnlyList<StoredJobRow> StoredJobs { get; set; } = [];

        public IReadOnlyList<StoredProgramRow> StoredPrograms { get; set; } = [];

        public IReadOnlyList<ShopRow> Shop { get; set; } = [];

        public long? SelectedStoredProgram { get; set; }

        public string StoreMessage { get; set; } = string.Empty;

        public event EventHandler? StoreRefreshRequested;

        public event EventHandler? OpenStoredProgramRequested;

        public void Refresh() => StoreRefreshRequested?.Invoke(this, EventArgs.Empty);

        public void Open() => OpenStoredProgramRequested?.Invoke(this, EventArgs.Empty);
    }

    private sealed class ServiceBackend(JobService service) : IStoreBackend
    {
        public string StoreDisplay => service.Store.Display;

        public IReadOnlyList<JobHistoryView> JobHistory() => service.JobHistory();

        public IReadOnlyList<StoredProgramView> StoredPrograms() => service.StoredPrograms();

        public IReadOnlyList<ShopMachineView> Shop() => service.ShopViews();

        public (string Path, string? Profile) StoredProgramFile(long id) => service.StoredProgramFile(id);
    }

    private (StorePresenter Presenter, StoreLocation Store, long Good, long Bad, long Job) Setup(HmiLanguage language = HmiLanguage.English, bool byRevision = false)
    {
        var store = StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        var good = Path.Combine(_folder.NewFolder("p"), "part.nc");
        File.WriteAllText(good, $"({Guid.NewGuid():N})\nG21 G90\nG0 X1 Y1\nG1 X5 F300\nM30\n", new UTF8Encoding(false));
        var bad = Path.Combine(_folder.NewFolder("p"), "bad.nc");
        File.WriteAllText(bad, "G1 X1 Q#\nM30\n", new UTF8Encoding(false));
        long goodId, badId, jobId;
        using (var programs = ProgramStores.Open(store))
        {
            goodId = programs.ImportRevision(good, MachineProfile.Resolve("linuxcnc-mill")).Id;
            badId = programs.ImportRevision(bad, MachineProfile.Default).Id;
        }

        using (var jobs = JobStores.Open(store))
        {
            jobId = jobs.CreateJob(good, "abc", "m.json", StrategyKind.Chunk, "sim", null, history: new JobHistoryStart(goodId, "station-1", "mill-1", 5));
            jobs.RecordEnd(jobId, "completed", 5, 5, 0, 0);
        }

        var service = new JobService(new JobServiceOptions { Store = store });
        var presenter = new StorePresenter(_view, new ServiceBackend(service), (path, profile) =>
        {
            _opened.Add((path, profile));
            return Task.CompletedTask;
        })
        {
            Language = () => language,
            OpenRevision = byRevision ? (id, path, profile) =>
            {
                _openedRevisions.Add(id);
                _opened.Add((path, profile));
                return Task.CompletedTask;
            }
            : null,
        };
        return (presenter, store, goodId, badId, jobId);
    }

    [Fact]
    public async Task The_page_lists_the_stores_jobs_and_programs_as_jobs_and_programs_json_do()
    {
        var (p, store, good, bad, job) = Setup();
        _view.StoreLocationText.Should().Be(store.Display);
        _view.Refresh();
        await p.WhenIdleAsync();

        _view.StoredJobs.Should().ContainSingle().Which.Should().BeEquivalentTo(new
        {
            Id = job, Program = $"#{good} part.nc", Station = "station-1", Machine = "mill-1", Outcome = "completed", Blocks = "5/5",
        });
        _view.StoredJobs[0].Ended.Should().NotBeEmpty();
        _view.StoredPrograms.Select(r => r.Id).Should().Equal(bad, good); // newest first
        _view.StoredPrograms.Single(r => r.Id == good).Should().BeEquivalentTo(new { Name = "part.nc", Profile = "linuxcnc-mill", Blocks = 4L, Errors = 0 });
        _view.StoredPrograms.Single(r => r.Id == bad).Errors.Should().BeGreaterThan(0);
        _view.StoreMessage.Should().Contain("1 jobs, 2 programs");
    }

    [Fact]
    public async Task In_Chinese_the_page_shows_its_outcomes_and_messages_in_Chinese()
    {
        var (p, _, _, _, _) = Setup(HmiLanguage.Chinese);
        _view.Refresh();
        await p.WhenIdleAsync();
        _view.StoredJobs.Single().Outcome.Should().Be("已完成");
        _view.StoreMessage.Should().Contain("1 个作业").And.Contain("2 个程序");
        _view.Open();
        await p.WhenIdleAsync();
        _view.StoreMessage.Should().Be("请先选择一个程序。");
    }

    [Fact]
    public void Every_Store_page_text_has_a_zh_CN_entry()
    {
        var ids = Enum.GetValues<TextId>().Where(id => id.ToString().StartsWith("Store", StringComparison.Ordinal) || id == TextId.TabStore).ToList();
        ids.Should().HaveCountGreaterThan(20, "the tab, labels, buttons, 12 column headers, messages and outcomes");
        foreach (var id in ids)
        {
            var zh = HmiText.Get(id, HmiLanguage.Chinese);
            zh.Should().MatchRegex(@"[\u4e00-\u9fff]", $"{id} needs a Chinese text").And.NotBe(HmiText.Get(id, HmiLanguage.English));
        }
    }

    [Fact]
    public async Task Open_hands_the_revision_id_to_the_program_screen_so_its_job_records_it()
    {
        var (p, _, good, _, _) = Setup(byRevision: true);
        _view.SelectedStoredProgram = good;
        _view.Open();
        await p.WhenIdleAsync();
        _openedRevisions.Should().Equal(good);
        _opened.Single().Profile.Should().Be("linuxcnc-mill");
    }

    [Fact]
    public async Task The_page_shows_the_shop_as_shop_prints_it_who_holds_each_machine_and_the_current_line()
    {
        var (p, store, good, _, job) = Setup();
        using (var jobs = JobStores.Open(store))
        {
            var running = jobs.CreateJob("/parts/other.nc", "def", "m.json", StrategyKind.Chunk, "tcp://10.0.0.7:1025", null, history: new JobHistoryStart(good, "cell-2", "mill-2", 40));
            jobs.SaveCheckpoint(running, new Checkpoint(17, 1, new StreamPosition(1, 3), true, 1, SessionState.Running, DateTimeOffset.UtcNow), durable: true, executed: 12);
        }

        await using (var lease = MachineLease.Take(store, "mill-2", "cell-2", null, StationSettings.Default))
        {
            _view.Refresh();
            await p.WhenIdleAsync();
            _view.Shop.Select(r => r.Machine).Should().Equal("mill-1", "mill-2");
            _view.Shop[0].Should().BeEquivalentTo(new { Station = "–", Job = job.ToString(System.Globalization.CultureInfo.InvariantCulture), Program = $"#{good} part.nc", Outcome = "completed", Blocks = "5/5", Lease = "free" });
            var leased = _view.Shop[1];
            leased.Station.Should().Be("cell-2");
            leased.Program.Should().Be($"#{good} other.nc");
            leased.Line.Should().Be("17", "the current line is the latest checkpoint's");
            leased.Lease.Should().StartWith("leased, beat ");
        }

        _view.Refresh();
        await p.WhenIdleAsync();
        _view.Shop[1].Should().BeEquivalentTo(new { Station = "–", Lease = "free" }, "the lease was given back");
    }

    [Fact]
    public async Task Open_writes_the_revisions_exact_source_and_opens_it_under_its_profile()
    {
        var (p, _, good, _, _) = Setup();
        _view.SelectedStoredProgram = good;
        _view.Open();
        await p.WhenIdleAsync();
        _opened.Should().ContainSingle();
        var (path, profile) = _opened[0];
        profile.Should().Be("linuxcnc-mill");
        Path.GetFileName(path).Should().Be("part.nc");
        File.ReadAllText(path).Should().Contain("G1 X5 F300");
        _view.StoreMessage.Should().StartWith($"opened program {good}");
    }

    [Fact]
    public async Task A_revision_with_errors_or_none_selected_is_not_opened_and_the_page_says_why()
    {
        var (p, _, _, bad, _) = Setup();
        _view.Open();
        await p.WhenIdleAsync();
        _view.StoreMessage.Should().Be("Select a program first.");

        _view.SelectedStoredProgram = bad;
        _view.Open();
        await p.WhenIdleAsync();
        _view.StoreMessage.Should().Contain("errors: it cannot run");

        _view.SelectedStoredProgram = 999_999;
        _view.Open();
        await p.WhenIdleAsync();
        _view.StoreMessage.Should().Contain("no program 999999");
        _opened.Should().BeEmpty();
    }
}
