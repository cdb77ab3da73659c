using PmacStream.Core.Tests.Preparation;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Jobs;

/// <summary>The job service's prepare step: the check gate under the machine profile and the split cache.</summary>
public sealed class PrepareTests : IDisposable
{
    private readonly TempProgram _clean = new(Program(2500));
    private readonly TestFolder _temp = new("prep");
    private readonly JobService _service;

    public PrepareTests() => _service = new(new JobServiceOptions { JobDatabase = Path.Combine(_temp.Path, "jobs.db") });

    public void Dispose()
    {
        _clean.Dispose();
        _temp.Dispose();
    }

    private static string Program(int moves, string? extra = null) => TestPrograms.Text(TestPrograms.Metric + "G01 F1200\n", moves, TestPrograms.Grid(40), after: i => i == moves / 2 ? extra : null);

    private Task<PreparedProgram> Prepare(TempProgram p, RunSettings settings, bool force = false, MachineProfile? profile = null) =>
        _service.PrepareAsync(new PrepareRequest(p.SourcePath, settings) { Force = force, Profile = profile ?? MachineProfile.Default });

    [Fact]
    public async Task Fewer_lines_per_chunk_than_the_earlier_split_splits_again()
    {
        var first = await Prepare(_clean, RunSettings.Default);
        first.Reused.Should().BeFalse();
        first.Program.Manifest.Chunks.Should().HaveCount(3);

        var second = await Prepare(_clean, RunSettings.Default with { BlocksPerChunk = 500 });
        second.Reused.Should().BeFalse("the cached split was made with 1000 lines per chunk");
        second.Program.Manifest.Chunks.Should().OnlyContain(c => c.BlockCount <= 500).And.HaveCount(6);
        ChunkManifest.Load(Path.Combine(second.Program.Folder, ChunkManifest.FileName)).BlocksPerChunk.Should().Be(500, "the split on disk is the new one");
    }

    [Fact]
    public async Task The_same_source_and_options_reuse_the_split_and_any_difference_does_not()
    {
        await Prepare(_clean, RunSettings.Default);
        (await Prepare(_clean, RunSettings.Default)).Reused.Should().BeTrue();
        (await Prepare(_clean, RunSettings.Default, force: true)).Reused.Should().BeTrue("a checked split of the same bytes is what a forced one would be");

        (await Prepare(_clean, RunSettings.Default with { ChunkWords = 5000 })).Reused.Should().BeFalse("another word budget");
        (await Prepare(_clean, RunSettings.Default with { ChunkWords = 5000 })).Reused.Should().BeTrue();
        (await Prepare(_clean, RunSettings.Default with { ChunkWords = 5000, FeedVariable = "P600" })).Reused.Should().BeFalse("another feed variable");
        var tail = MachineProfile.Parse(MachineProfile.Default.ToJson().Replace("\"programTail\": \"M05\"", "\"programTail\": \"M03 M05\"", StringComparison.Ordinal), "paper.json");
        (await Prepare(_clean, RunSettings.Default with { ChunkWords = 5000, FeedVariable = "P600" }, profile: tail)).Reused.Should().BeFalse("another profile (and tail)");

        File.AppendAllText(_clean.SourcePath, "G01 X1 Y1\n");
        (await Prepare(_clean, RunSettings.Default with { ChunkWords = 5000, FeedVariable = "P600" }, profile: tail)).Reused.Should().BeFalse("the source changed");
    }

    [Fact]
    public async Task A_program_with_profile_errors_is_refused_with_every_error_and_nothing_is_written()
    {
        using var bad = new TempProgram(Program(300, "G00 G01 X5\nG77 X3\nG01 X4 U2"));
        var expected = new List<Diagnostic>();
        new Checker(MachineProfile.Default).CheckFile(bad.SourcePath, d =>
        {
            if (d.Severity == Severity.Error)
            {
                expected.Add(d);
            }
        });
        expected.Should().HaveCountGreaterThanOrEqualTo(3, "two codes of one group, an unknown code and an unknown axis word");

        var act = () => Prepare(bad, RunSettings.Default);
        var refused = (await act.Should().ThrowAsync<ProgramRefusedException>()).Which;
        refused.ErrorCount.Should().Be(expected.Count);
        refused.Lines("bad.nc").Should().Equal(expected.Select(d => d.Format("bad.nc")));
        Directory.Exists(Splitter.DefaultOutDir(bad.SourcePath)).Should().BeFalse("a refused program leaves no chunks");
    }

    [Fact]
    public async Task A_forced_split_is_not_reused_without_force_the_check_refuses_again()
    {
        using var bad = new TempProgram(Program(300, "G77 X3"));
        var forced = await Prepare(bad, RunSettings.Default, force: true);
        forced.Program.Manifest.CheckedProfile.Should().BeNull("a forced split was not checked");

        var act = () => Prepare(bad, RunSettings.Default);
        (await act.Should().ThrowAsync<ProgramRefusedException>()).Which.Diagnostics.Should().ContainSingle(d => d.Code == "E104");
        (await Prepare(bad, RunSettings.Default, force: true)).Reused.Should().BeTrue("forcing again takes the forced split");
    }

    [Fact]
    public async Task Codes_the_controller_cannot_run_yet_are_refused_for_a_job_each_at_its_first_use_unless_forced()
    {
        // Exact stop and tapping mode have no routine yet: the PMAC would skip them and blend or cut as if never asked.
        using var p = new TempProgram(Program(300, "G16\nG90\nG63\nG64"));
        var act = () => Prepare(p, RunSettings.Default);
        var refused = (await act.Should().ThrowAsync<ProgramRefusedException>()).Which;

        refused.NotRunnableCodes.Should().BeEquivalentTo(new Dictionary<string, int> { ["G16"] = 154, ["G63"] = 156 });
        refused.Profile.Should().Be(MachineProfile.DefaultName);
        refused.Lines("p.nc").Should().Equal(
            "p.nc:154:1: error E127: G16 (polar coordinate command) cannot run on the controller yet under profile 'fanuc-mill': the PMAC would skip the code and run the rest of the block",
            "p.nc:156:1: error E127: G63 (tapping mode) cannot run on the controller yet under profile 'fanuc-mill': the PMAC would skip the code and run the rest of the block");
        refused.ErrorCount.Should().Be(2);

        // The split itself is the program's (split writes it too) and is reused; only running it is refused.
        var forced = await Prepare(p, RunSettings.Default, force: true);
        forced.Program.Manifest.NotYetCodes.Should().ContainKeys("G16", "G63");
        var again = () => Prepare(p, RunSettings.Default);
        await again.Should().ThrowAsync<ProgramRefusedException>("forcing once does not open the gate for the next job");
    }

    [Fact]
    public async Task A_job_resumed_from_a_forced_split_or_with_codes_not_run_yet_needs_force_again()
    {
        using var notYet = new TempProgram(Program(50, "G16"));
        var manifest = (await Prepare(notYet, RunSettings.Default, force: true)).Program.Manifest;
        var gate = () => ProgramGate.EnsureRunnable(notYet.SourcePath, manifest, MachineProfile.Default, force: false);
        gate.Should().Throw<ProgramRefusedException>().Which.NotRunnableCodes.Should().ContainKey("G16");
        ProgramGate.EnsureRunnable(notYet.SourcePath, manifest, MachineProfile.Default, force: true);

        using var bad = new TempProgram(Program(50, "G77 X3"));
        var forcedSplit = (await Prepare(bad, RunSettings.Default, force: true)).Program.Manifest;
        var refused = () => ProgramGate.EnsureRunnable(bad.SourcePath, forcedSplit, MachineProfile.Default, force: false);
        refused.Should().Throw<ProgramRefusedException>().Which.ForcedSplit.Should().BeTrue();
    }

    [Fact]
    public void A_resume_reads_the_profile_the_job_ran_under_and_refuses_one_that_changed()
    {
        var file = Path.Combine(_clean.Folder, "mine.json");
        File.WriteAllText(file, MachineProfile.Default.ToJson().Replace("\"name\": \"fanuc-mill\"", "\"name\": \"mine\"", StringComparison.Ordinal));
        var mine = MachineProfile.Resolve(file);
        mine.Source.Should().Be(Path.GetFullPath(file));
        var record = new PmacStream.Streaming.JobRecord(7, _clean.SourcePath, new string('a', 64), "m.json", PmacStream.Streaming.StrategyKind.Chunk, "sim", null, "", null,
            DateTimeOffset.UnixEpoch, Profile: mine.Source, ProfileIdentity: mine.Identity);

        JobService.ProfileOf(record).Identity.Should().Be(mine.Identity, "the record names the file");
        var other = () => JobService.ProfileOf(record, "grbl");
        other.Should().Throw<JobException>().WithMessage("job 7 ran under machine profile *mine.json (mine@*); the profile asked for, grbl, is grbl@*: the profile changed since the job started*");

        File.WriteAllText(file, File.ReadAllText(file).Replace("\"toolCount\": 9999", "\"toolCount\": 12", StringComparison.Ordinal));
        var changed = () => JobService.ProfileOf(record);
        changed.Should().Throw<JobException>().WithMessage("*mine.json now reads as mine@*: the profile changed since the job started*");

        var older = record with { Profile = null, ProfileIdentity = null };
        JobService.ProfileOf(older).Name.Should().Be(MachineProfile.DefaultName, "a record of an older version does not say: the default");
    }

    [Fact]
    public async Task Bad_settings_and_missing_programs_are_bad_requests()
    {
        var noFile = () => _service.PrepareAsync(new PrepareRequest(Path.Combine(_clean.Folder, "none.nc"), RunSettings.Default));
        (await noFile.Should().ThrowAsync<JobException>()).Which.Kind.Should().Be(JobErrorKind.BadRequest);
        var badWindow = () => Prepare(_clean, RunSettings.Default with { WindowStart = 0.9 });
        (await badWindow.Should().ThrowAsync<JobException>().WithMessage("*window*")).Which.Kind.Should().Be(JobErrorKind.BadRequest);
    }

    [Fact]
    public async Task A_start_plan_needs_a_block_at_or_after_its_line()
    {
        var prepared = await Prepare(_clean, RunSettings.Default);
        _service.PlanStart(prepared.Program, 1200, RunSettings.Default).Line.Should().BeGreaterThanOrEqualTo(1200);
        var act = () => _service.PlanStart(prepared.Program, 99_999, RunSettings.Default);
        act.Should().Throw<JobException>().Which.Kind.Should().Be(JobErrorKind.BadRequest);
    }

    [Fact]
    public async Task Connecting_to_the_simulator_needs_a_host_that_has_one_and_reading_jobs_needs_a_database()
    {
        var act = () => _service.ConnectAsync(PmacStream.Pmac.ConnectionSpec.Simulator);
        (await act.Should().ThrowAsync<JobException>().WithMessage("*no built-in simulator*")).Which.Kind.Should().Be(JobErrorKind.BadRequest);
        var find = () => _service.FindJob(null);
        find.Should().Throw<JobException>().WithMessage("*no job database*");
        File.Exists(_service.JobDatabase).Should().BeFalse("reading jobs creates no database");
        _service.FindInterrupted(_clean.SourcePath).Should().BeNull();
    }
}
