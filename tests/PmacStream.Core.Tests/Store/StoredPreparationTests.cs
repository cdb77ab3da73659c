using System.Text;
using System.Text.Json.Nodes;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;

namespace PmacStream.Core.Tests.Store;

/// <summary>
/// A stored revision's preparation is kept with it: reused (nothing split) while the chunk shape and the machine
/// inputs are the same, written from the store into a folder that lost it (another station), and prepared again and
/// stored beside the first when a tool radius or the chunk size changes; the chunks equal a fresh split's bytes.
/// </summary>
public sealed class StoredPreparationTests : IDisposable
{
    private readonly TestFolder _folder = new("stored-preparation");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task A_preparation_is_reused_only_while_its_inputs_are_the_same(string engine)
    {
        var location = Location(engine);
        var file = Path.Combine(_folder.NewFolder("src"), "part.nc");
        var text = new StringBuilder($"({Guid.NewGuid():N})\nG21 G90 G17\nT1 M06\nS5000 M03\nG0 X0 Y0 Z5\nG1 Z-1 F300\nG1 X10 Y0\n");
        for (var i = 0; i < 120; i++)
        {
            text.Append(i % 2 == 0 ? $"X{20 + i}. Y{i}.\n" : $"Y{i + 1}.\n");
        }

        File.WriteAllText(file, text.Append("G0 Z10\nM30\n").ToString());
        var profile = WithRadius(1.0);
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(file, profile).Id;
        }

        var service = new JobService(new JobServiceOptions { Store = location });
        var settings = RunSettings.Default with { Shape = RunSettings.Default.Shape with { BlocksPerChunk = 20 } };
        var outDir = Path.Combine(_folder.Path, "chunks");
        PreparedProgram Prepare(MachineProfile p, RunSettings s) =>
            service.PrepareAsync(new PrepareRequest(file, s) { Profile = p, ProgramId = id, OutDir = outDir }).GetAwaiter().GetResult();

        var first = Prepare(profile, settings);
        (service.PreparationsStored, service.PreparationsReused).Should().Be((1L, 0L), "the first run splits and stores");
        var fresh = Splitter.Split(file, settings.ToSplitOptions(profile, Path.Combine(_folder.Path, "fresh"), false));
        Chunks(first.Program.Folder).Should().Equal(Chunks(fresh.OutputDirectory), "the stored split is the split");

        Prepare(profile, settings).Reused.Should().BeTrue();
        (service.PreparationsStored, service.PreparationsReused).Should().Be((1L, 1L), "the same inputs: nothing split");

        // Another station: the folder is not there; the chunks come from the store, byte for byte.
        Directory.Delete(outDir, true);
        var elsewhere = Prepare(profile, settings);
        (service.PreparationsStored, service.PreparationsReused).Should().Be((1L, 2L));
        Chunks(elsewhere.Program.Folder).Should().Equal(Chunks(fresh.OutputDirectory), "written from the store, as split");
        elsewhere.Program.Manifest.SourcePath.Should().Be(Path.GetFullPath(file), "the manifest names this station's copy");

        Prepare(WithRadius(1.5), settings);
        service.PreparationsStored.Should().Be(2, "another tool radius is another machine input (a compensated path moves): prepared again");
        Prepare(profile, settings with { Shape = settings.Shape with { BlocksPerChunk = 30 } });
        service.PreparationsStored.Should().Be(3, "another chunk size cuts other chunks");
        Prepare(profile, settings);
        (service.PreparationsStored, service.PreparationsReused).Should().Be((3L, 3L), "the first inputs again: the first preparation");

        using var check = ProgramStores.Open(location);
        check.ListPreparations(id).Should().HaveCount(3);
    }

    private static List<(string, string)> Chunks(string folder) =>
        Directory.GetFiles(folder, "*.pmc").Order(StringComparer.Ordinal).Select(f => (Path.GetFileName(f), Convert.ToHexString(System.Security.Cryptography.SHA256.HashData(File.ReadAllBytes(f))))).ToList();

    private static MachineProfile WithRadius(double radius)
    {
        var json = JsonNode.Parse(MachineProfile.Default.ToJson())!;
        json["toolRadii"] = new JsonObject { ["1"] = radius };
        return MachineProfile.Parse(json.ToJsonString());
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
