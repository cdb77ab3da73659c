using System.Text;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// The job service's preparation imports a file that is not stored yet (<see cref="PrepareRequest.Import"/>, what
/// <c>stream FILE</c> asks for, so every face shares it): the revision is named by the prepared program, a file stored
/// already is found by its SHA-256 and not imported again, and a program with errors is stored with its diagnostics
/// while nothing is split. On both engines.
/// </summary>
public sealed class PrepareImportTests : IDisposable
{
    private readonly TestFolder _folder = new("prepare-import");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_file_is_imported_once_by_the_preparation_and_a_program_with_errors_is_stored_and_not_split(string engine)
    {
        var location = Location(engine);
        var file = Path.Combine(_folder.Path, "part.nc");
        File.WriteAllText(file, $"({Guid.NewGuid():N})\nG21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F300\nG1 X10\nG1 Y10\nG0 Z5\nM30\n", new UTF8Encoding(false));
        var service = new JobService(new JobServiceOptions { Store = location });
        var first = await service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Import = true, OutDir = Path.Combine(_folder.Path, "chunks") });
        first.ProgramId.Should().NotBeNull("the file was imported as a revision");
        service.PreparationsStored.Should().Be(1, "its preparation is kept with the revision");
        int revisions;
        using (var store = ProgramStores.Open(location))
        {
            store.GetProgram(first.ProgramId!.Value)!.Sha256.Should().BeEquivalentTo(FileHash.Sha256Hex(file, CancellationToken.None));
            revisions = store.ListRevisions().Count;
        }

        var again = await service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Import = true, OutDir = Path.Combine(_folder.Path, "chunks") });
        again.ProgramId.Should().Be(first.ProgramId, "found by its SHA-256");
        service.PreparationsReused.Should().Be(1);
        using (var store = ProgramStores.Open(location))
        {
            store.ListRevisions().Should().HaveCount(revisions, "not imported again");
        }

        var bad = Path.Combine(_folder.Path, "bad.nc");
        File.WriteAllText(bad, $"({Guid.NewGuid():N})\nG21 G90\nG0 X0 Y0 Z5\nG1 X10 F300 Q\n", new UTF8Encoding(false));
        var badChunks = Path.Combine(_folder.Path, "bad-chunks");
        var refused = () => service.PrepareAsync(new PrepareRequest(bad, RunSettings.Default) { Import = true, OutDir = badChunks });
        (await refused.Should().ThrowAsync<ProgramRefusedException>()).Which.ErrorCount.Should().BeGreaterThan(0);
        File.Exists(Path.Combine(badChunks, ChunkManifest.FileName)).Should().BeFalse("nothing split");
        using (var store = ProgramStores.Open(location))
        {
            var stored = store.FindRevision(FileHash.Sha256Hex(bad, CancellationToken.None), MachineProfile.Default.Name);
            stored.Should().NotBeNull("a program with errors is stored with its diagnostics");
            stored!.Errors.Should().BeGreaterThan(0);
            store.GetDiagnostics(stored.Id).Should().Contain(d => d.Severity == Severity.Error);
        }
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
