using System.Text;
using PmacStream.Cli;
using PmacStream.Cli.Commands;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// A revision whose program was expanded (o-word loops here) keeps its source map with it (migration 10), on both
/// engines: every stored block (numbered by expanded line, as <c>M0==</c> counts them) says where it came from, and a
/// start at a source line that runs more than once is served for the run named (<c>--call</c>) or refused with the runs.
/// </summary>
public sealed class StoredExpansionMapTests : IDisposable
{
    private readonly TestFolder _folder = new("stored-expansion-map");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void An_expanded_revision_keeps_where_each_block_came_from_and_a_start_names_the_run(string engine)
    {
        var location = Location(engine);
        var source = Path.Combine(_folder.Path, "loop.ngc");
        // Line 5 runs three times (the loop's body); a comment on top makes a new revision on a shared server.
        File.WriteAllText(source, $"({Guid.NewGuid():N})\nG21 G90 G17\n#1 = 0\no100 while [#1 LT 3]\nG01 X[#1] Y1 F600\n#1 = [#1 + 1]\no100 endwhile\nM2\n", new UTF8Encoding(false));
        var plain = Path.Combine(_folder.Path, "plain.nc");
        File.WriteAllText(plain, $"({Guid.NewGuid():N})\nG21 G90\nG0 X1 Y1\nG1 X2 F100\nM30\n", new UTF8Encoding(false));
        long id, plainId;
        using (var store = ProgramStores.Open(location))
        {
            id = store.ImportRevision(source, MachineProfile.Named("linuxcnc-mill")!).Id;
            plainId = store.ImportRevision(plain, MachineProfile.Default).Id;
            store.ReadExpansionMap(plainId).Should().BeNull("a program without subprograms or macros is its own map");
            var map = store.ReadExpansionMap(id);
            map.Should().NotBeNull();
            var runs = map!.Occurrences(5, null);
            runs.Should().HaveCount(3, "the loop's body ran three times");
            var moves = store.ReadStoredBlocks(id).Where(b => b.Block.Motion != MotionKind.None).Select(b => b.Block.Line).ToList();
            moves.Should().Equal(runs.Select(r => (int)r.Expanded), "the stored moves are the expanded lines the map names");
            map.Describe(runs[2].Expanded).Should().Contain("line 5").And.Contain("iteration 3");
        }

        var stdout = new StringWriter();
        ProgramStartCommand.Run(location, id, 5, false, false, stdout, new StringWriter(), CancellationToken.None, run: (2, null)).Should().Be(CliGlobals.Ok);
        var lines = stdout.ToString().Split('\n');
        lines[0].Should().Contain("starting at line 5, iteration 2");
        lines[1].Should().Match("start at line *");

        var ambiguous = () => ProgramStartCommand.Run(location, id, 5, false, false, new StringWriter(), new StringWriter(), CancellationToken.None);
        ambiguous.Should().Throw<CliException>().Which.Message.Should().Contain("runs 3 times").And.Contain("--call 3");
        var notExpanded = () => ProgramStartCommand.Run(location, plainId, 3, false, false, new StringWriter(), new StringWriter(), CancellationToken.None, run: (1, null));
        notExpanded.Should().Throw<CliException>().Which.Message.Should().Contain("no stored source map");
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
