using System.Text;
using PmacStream.Cli;
using PmacStream.Cli.Commands;
using PmacStream.GCode;
using PmacStream.Preparation.Store;
using PmacStream.Preview;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// The preview of a stored revision draws its stored decoded blocks: the toolpath is the file preview's, segment for
/// segment (cycles hole by hole from the stored holes), and `preview --program ID` draws after the file is gone, on
/// SQLite and (where <c>PMACSTREAM_TEST_PG</c> names a server) on PostgreSQL.
/// </summary>
public sealed class StoredPreviewTests : IDisposable
{
    /// <summary>Work offsets, G52/G92 shifts, arcs, inches, incremental moves and cycles (repeated in G91).</summary>
    private const string Busy =
        "G21 G90 G17\nG10 L2 P2 X30. Y-20. Z5.\nG55\nG00 X0 Y0 Z10.\nG01 X5. F300.\nG52 X10. Y10.\nX10. Y5.\nG52 X0 Y0\nG00 X10. Y10.\n" +
        "G02 X20. Y10. I5. J0 F400\nG03 X10. Y10. R5.\nG81 X10. Y10. Z-5. R2. F200\nX20.\nG91 X5. Y5. K3\nG90 G80\n" +
        "G20\nG00 X1. Y1. Z0.5\nG01 Z-0.1 F10.\nG21\nG83 X40. Y40. Z-8. R1. Q2. F100\nG80\nG92 X5. Y10.\nG01 X0 Y0\nG92.1\nM30\n";

    private readonly TestFolder _folder = new("stored-preview");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void The_stored_blocks_draw_the_toolpath_the_file_draws(string engine)
    {
        var location = Location(engine);
        var files = new List<string> { Program("busy.nc", Busy) };
        files.AddRange(Requires.Corpus().Where(f => new FileInfo(f).Length < 500_000).Select(Copy));
        using var store = ProgramStores.Open(location);
        var cycles = 0;
        foreach (var file in files)
        {
            var id = store.ImportRevision(file, MachineProfile.Default).Id;
            var fromFile = new GCodeToolpathSource(file, MachineProfile.Default).ReadSegments().ToList();
            var info = store.GetProgram(id)!;
            var stored = new DecodedBlockToolpathSource(() => store.ReadStoredBlocks(id).Select(b => (b.Block, b.Holes)), info.Blocks, info.Name!, [], 0);
            var fromStore = stored.ReadSegments().ToList();
            fromStore.Should().Equal(fromFile, $"{Path.GetFileName(file)} from the store is drawn as from the file");
            stored.CyclesWithoutHoles.Should().Be(0);
            cycles += store.ReadStoredBlocks(id).Count(b => b.Holes is not null);
        }

        cycles.Should().BeGreaterThanOrEqualTo(5, "the busy program's cycle blocks keep their holes");
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void Preview_program_draws_a_revision_whose_file_is_gone(string engine)
    {
        var location = Location(engine);
        var file = Program("gone.nc", Busy);
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(file, MachineProfile.Default).Id;
        }

        var fromFile = Run(new PreviewArgs(file, Path.Combine(_folder.Path, "file.png"), "400x300", "xy", null, "en", null, false));
        fromFile.Code.Should().Be(0, fromFile.Stderr);
        File.Delete(file); // nothing of the file can be read: the picture comes from the store or not at all

        var png = Path.Combine(_folder.Path, "stored.png");
        var stored = Run(new PreviewArgs(null, png, "400x300", "xy", null, "en", null, false, id, location.Target));
        stored.Code.Should().Be(0, stored.Stderr);
        File.Exists(png).Should().BeTrue();
        stored.Stdout.Split('\n')[0].Replace("stored.png", "X.png", StringComparison.Ordinal)
            .Should().Be(fromFile.Stdout.Split('\n')[0].Replace("file.png", "X.png", StringComparison.Ordinal), "the same moves are drawn");
        stored.Stdout.Split('\n')[1].Should().Be(fromFile.Stdout.Split('\n')[1], "the same extents");

        var both = Run(new PreviewArgs(file, png, "400x300", "xy", null, "en", null, false, id, location.Target));
        both.Code.Should().Be(CliGlobals.UsageOrIo);
        both.Stderr.Should().Contain("not both");
        var missing = Run(new PreviewArgs(null, png, "400x300", "xy", null, "en", null, false, 987654321, location.Target));
        missing.Code.Should().NotBe(0);
        missing.Stderr.Should().Contain("no program 987654321");
    }

    [Fact]
    public void A_stored_program_with_errors_is_refused_from_its_stored_diagnostics()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "errors.db"));
        var file = Program("bad.nc", "G21 G90\nG00 X0 Y0\nG01 X10 F300\nG02 X20 Y0\nM30\n");
        long id;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(file, MachineProfile.Default).Id;
        }

        File.Delete(file);
        var png = Path.Combine(_folder.Path, "bad.png");
        var refused = Run(new PreviewArgs(null, png, "400x300", "xy", null, "en", null, false, id, location.Target));
        refused.Code.Should().Be(CliGlobals.Failed);
        refused.Stderr.Should().Contain($"program {id} (bad.nc)").And.Contain("error");
        File.Exists(png).Should().BeFalse();
    }

    private static (int Code, string Stdout, string Stderr) Run(PreviewArgs args)
    {
        var stdout = new StringWriter();
        var stderr = new StringWriter();
        try
        {
            var code = PreviewCommand.RunAsync(args, new CliConsole(stdout, stderr), CancellationToken.None).GetAwaiter().GetResult();
            // The command's progress ("preview  50.0% ...") goes to the same console: the result lines are the rest.
            var result = string.Join('\n', stdout.ToString().Split('\n').Where(l => !l.StartsWith("preview ", StringComparison.Ordinal)));
            return (code, result, stderr.ToString());
        }
        catch (CliException e)
        {
            return (e.ExitCode, stdout.ToString(), stderr + "pmacstream preview: " + e.Message);
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

    /// <summary>A copy whose content is this run's own (the PostgreSQL store is shared by every run): one comment line first.</summary>
    private string Copy(string corpus)
    {
        var path = Path.Combine(_folder.NewFolder("c"), Path.GetFileName(corpus));
        using var output = File.Create(path);
        output.Write(Encoding.ASCII.GetBytes($"({Guid.NewGuid():N})\n"));
        using var input = File.OpenRead(corpus);
        input.CopyTo(output);
        return path;
    }

    private string Program(string name, string text)
    {
        var path = Path.Combine(_folder.NewFolder("p"), name);
        File.WriteAllText(path, $"({Guid.NewGuid():N})\n" + text, new UTF8Encoding(false));
        return path;
    }
}
