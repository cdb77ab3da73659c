using PmacStream.GCode;
using PmacStream.GCode.Expansion;
using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;
using PmacStream.Streaming;

namespace PmacStream.Core.Tests.Jobs;

/// <summary>
/// Issue 27 item 2, tracking through the expansion on every face: a start names a source line, its run (<c>--call</c>)
/// and its file (<c>--file</c>) and is refused with the choices when ambiguous; the job record keeps where its line came
/// from (<c>source_location</c>, migration 8); the HMI's status shows it. A program without subprograms has no map.
/// </summary>
public sealed class SourceTrackingTests : IDisposable
{
    private readonly TestFolder _folder = new("tracking");

    public void Dispose() => _folder.Dispose();

    /// <summary>Main line 2 and O1002.nc line 2 share a number; O1002 runs three times from line 3, once more from line 4.</summary>
    private (string Path, ExpansionMap Map) Split()
    {
        File.WriteAllText(Path.Combine(_folder.Path, "O1002.nc"), "O1002\nG91 G01 X1. F100\nG90\nM99\n");
        var path = Path.Combine(_folder.Path, "main.nc");
        File.WriteAllText(path, "O0001\nG21 G90 G17 G00 X0 Y0 Z5.\nM98 P1002 L3\nM98 P1002\nG00 Z10.\nM30\n");
        var result = Splitter.Split(path, new SplitOptions { OutDir = Path.Combine(_folder.Path, "chunks"), CheckProfile = MachineProfile.Default });
        return (path, SourceLocations.MapOf(result.OutputDirectory) ?? throw new InvalidOperationException("no expansion map"));
    }

    [Fact]
    public void A_start_names_the_run_of_a_source_line_and_its_file_and_an_ambiguous_one_is_refused_with_the_choices()
    {
        var (_, map) = Split();
        var acrossFiles = () => SourceLocations.Resolve(map, 2, null, null);
        acrossFiles.Should().Throw<JobException>().WithMessage("*line 2 is a line of more than one file (main.nc, O1002.nc)*--file*");

        var calls = () => SourceLocations.Resolve(map, 2, null, "O1002");
        var refusal = calls.Should().Throw<JobException>().Which.Message;
        refusal.Should().Contain("runs 4 times").And.Contain("--call 1: O1002 line 2, call 1 of 3 from line 3")
            .And.Contain("--call 4: O1002 line 2, call 1 of 1 from line 4");

        var third = SourceLocations.Resolve(map, 2, 3, "O1002.nc");
        map.Describe(third).Should().Be("O1002 line 2, call 3 of 3 from line 3");
        SourceLocations.Resolve(map, 2, 3, "O1002").Should().Be(third, "the called program's name or its file's");
        SourceLocations.StartOptions(map, third).Should().Be("--from-line 2 --call 3 --file O1002.nc", "the way back to the same run");
        map.Describe(SourceLocations.Resolve(map, 5, null, null)).Should().Be("line 5", "a main line that runs once needs no call");
        var beyond = () => SourceLocations.Resolve(map, 2, 5, "O1002");
        beyond.Should().Throw<JobException>().WithMessage("*runs 4 times: --call 1 to 4*");
    }

    [Fact]
    public void A_start_from_an_expanded_line_replays_the_expansion_to_it()
    {
        var (path, map) = Split();
        var line = SourceLocations.Resolve(map, 2, 3, "O1002");
        var plan = StartFromLine.Plan(path, line, new StartPlanOptions { Profile = MachineProfile.Default });
        plan.Line.Should().Be(line);
        plan.GCode.Should().Contain(l => l.Contains("X2", StringComparison.Ordinal), "two incremental moves of X1 ran before the third call");
    }

    [Fact]
    public void A_program_without_subprograms_has_no_map_and_its_lines_are_its_source_lines()
    {
        var path = Path.Combine(_folder.Path, "plain.nc");
        File.WriteAllText(path, "O0001\nG21 G90 G00 X1.\nM30\n");
        var result = Splitter.Split(path, new SplitOptions { OutDir = Path.Combine(_folder.Path, "plain"), CheckProfile = MachineProfile.Default });
        SourceLocations.MapOf(result.OutputDirectory).Should().BeNull();
        SourceLocations.Describe(null, 2).Should().BeNull();
    }

    [Fact]
    public void The_job_record_keeps_where_its_line_came_from()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "jobs.db"));
        using var store = JobStores.Open(location);
        var id = store.CreateJob(Path.Combine(_folder.Path, "main.nc"), new string('c', 64), Path.Combine(_folder.Path, "manifest.json"), StrategyKind.Full, "sim", null);
        store.Get(id)!.SourceLocation.Should().BeNull("a job of a program without subprograms has none");
        store.SetSourceLocation(id, "O1002 line 2, call 3 of 3 from line 3");
        store.Get(id)!.SourceLocation.Should().Be("O1002 line 2, call 3 of 3 from line 3");
        store.SetSourceLocation(id, null);
        store.Get(id)!.SourceLocation.Should().BeNull();
    }

    [SkippableFact]
    public void The_job_record_keeps_where_its_line_came_from_on_postgres()
    {
        var (station, admin) = Requires.Postgres();
        if (admin is not null)
        {
            using (PgSchema.OpenMigrated(StoreLocation.Parse(admin)))
            {
            }
        }

        using var store = JobStores.Open(StoreLocation.Parse(station));
        var id = store.CreateJob(Path.Combine(_folder.Path, "main.nc"), new string('d', 64), Path.Combine(_folder.Path, "manifest.json"), StrategyKind.Full, "sim", null);
        store.SetSourceLocation(id, "O1002 line 2, call 1 of 3 from line 3");
        store.Get(id)!.SourceLocation.Should().Be("O1002 line 2, call 1 of 3 from line 3");
    }

    [Fact]
    public void The_status_panel_shows_the_executing_lines_source_location_when_the_program_was_expanded()
    {
        var running = new HmiJobStatus(HmiJobState.Running, 1, 7, 50, 100, null, TimeSpan.FromSeconds(3), null) { SourceLocation = "O1002 line 2, call 3 of 3 from line 3" };
        var shown = StatusStrip.Show(new StatusFacts(running, true, null, null, 100, RunSettings.Default, "full"), HmiLanguage.English);
        shown.CurrentLine.Should().Be("7 (O1002 line 2, call 3 of 3 from line 3)");
        var plain = StatusStrip.Show(new StatusFacts(running with { SourceLocation = null }, true, null, null, 100, RunSettings.Default, "full"), HmiLanguage.English);
        plain.CurrentLine.Should().Be("7", "a program without subprograms is shown as before");
    }
}
