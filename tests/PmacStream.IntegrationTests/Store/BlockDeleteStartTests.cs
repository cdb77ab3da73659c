using System.Text;
using PmacStream.Jobs;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// A start from a line restores what ran: with block delete on (the split's default), the blocks starting with
/// <c>/</c> before the start never ran, so neither their work offset nor their position is in the preamble. The store
/// decodes every block (as <c>programs import</c> does), so its states count them: such a start re-interprets the source
/// with block delete on instead; with block delete off the store's states are the program's and are read. Both engines.
/// </summary>
public sealed class BlockDeleteStartTests : IDisposable
{
    private readonly TestFolder _folder = new("block-delete-start");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_start_after_block_delete_blocks_restores_the_state_and_position_the_run_left(string engine)
    {
        var location = Location(engine);
        var file = Path.Combine(_folder.Path, "slash.nc");
        // Line 1 is a comment of its own (a new revision on a shared PostgreSQL store every run).
        File.WriteAllText(file, $"({Guid.NewGuid():N})\nG21 G90 G17 G54\nG0 X0 Y0 Z5\n/G55\n/G0 X50\nG1 Z-1 F300\nG1 X10 Y10\nG1 X20\nM30\n", new UTF8Encoding(false));
        var service = new JobService(new JobServiceOptions { Store = location });

        var on = await service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Import = true, OutDir = Path.Combine(_folder.Path, "on") });
        on.ProgramId.Should().NotBeNull();
        service.ImportedInSplitPass.Should().Be(0, "block delete on and a '/' block: the import runs by itself");
        var skipped = service.PlanStartFor(on.ProgramId, on.Program, 7, RunSettings.Default);
        service.StartFallbacks.Should().Be(1, "the store's states count the '/' blocks, which never ran");
        var text = string.Join("\n", skipped.GCode);
        text.Should().NotContain("G55", "line 4 was skipped").And.Contain("G54");
        text.Should().NotContain("X50", "line 5 was skipped: the block starts at X0");
        skipped.GCode.Should().Equal(service.PlanStart(on.Program, 7, RunSettings.Default).GCode);

        var offSettings = RunSettings.Default with { Shape = RunSettings.Default.Shape with { BlockDelete = false } };
        var off = await service.PrepareAsync(new PrepareRequest(file, offSettings) { Import = true, OutDir = Path.Combine(_folder.Path, "off") });
        off.ProgramId.Should().Be(on.ProgramId, "the same revision");
        var ran = service.PlanStartFor(off.ProgramId, off.Program, 7, offSettings);
        service.StartsFromStore.Should().Be(1, "with block delete off every block ran, as the store decoded them");
        var all = string.Join("\n", ran.GCode);
        all.Should().Contain("G55").And.Contain("X50");
        ran.GCode.Should().Equal(service.PlanStart(off.Program, 7, offSettings).GCode, "the store's plan is the re-interpreted one");
    }

    private StoreLocation Location(string engine)
    {
        if (engine == "sqlite")
        {
            return StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        }

        var (station, admin) = Requires.Postgres();
        if (admin is not null)
        {
            using (PgSchema.OpenMigrated(StoreLocation.Parse(admin)))
            {
            }
        }

        return StoreLocation.Parse(station);
    }
}
