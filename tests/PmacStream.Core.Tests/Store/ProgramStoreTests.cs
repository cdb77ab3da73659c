using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Core.Tests.Store;

public sealed class ProgramStoreTests : IDisposable
{
    private readonly TestFolder _temp = new("store");

    private string Demo => RepoRoot.DemoProgram;

    public void Dispose()
    {
        Microsoft.Data.Sqlite.SqliteConnection.ClearAllPools();
        _temp.Dispose();
    }

    private static List<DecodedBlock> Interpret(string file)
    {
        var list = new List<DecodedBlock>();
        new Checker(MachineProfile.Default).CheckFile(file, _ => { }, list.Add);
        return list;
    }

    [Fact]
    public void Import_stores_every_block_with_program_row_and_hash()
    {
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "p.db"));
        var (id, summary) = store.Import(Demo, MachineProfile.Default);
        var info = store.GetProgram(id)!;
        info.Blocks.Should().Be(summary.Blocks);
        info.Lines.Should().Be(summary.Lines);
        info.Errors.Should().Be(0);
        info.Size.Should().Be(new FileInfo(Demo).Length);
        info.Sha256.Should().Be(Convert.ToHexStringLower(System.Security.Cryptography.SHA256.HashData(File.ReadAllBytes(Demo))));
        info.CheckSummary.Should().Be(summary.ToString());
        store.FindBySha256(info.Sha256)!.Id.Should().Be(id);
        store.ReadBlocks(id).Count().Should().Be((int)summary.Blocks);
    }

    [Fact]
    public void Stored_blocks_read_back_equal_to_the_interpreted_ones()
    {
        var expected = Interpret(Demo);
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "p.db"));
        var (id, _) = store.Import(Demo, MachineProfile.Default);

        var all = store.ReadBlocks(id).ToList();
        all.Should().HaveCount(expected.Count);
        for (var i = 0; i < all.Count; i++)
        {
            all[i].Should().Be(expected[i], $"block {i} (line {expected[i].Line})");
        }

        var one = expected[100];
        store.GetBlockAtLine(id, one.Line).Should().Be(one);
        store.GetBlockAtLine(id, 1).Should().BeNull("line 1 is the % tape mark");
        store.GetBlockAtOrAfterLine(id, 1)!.Line.Should().Be(expected[0].Line);

        var range = store.GetRange(id, expected[10].Line, expected[20].Line);
        range.Should().Equal(expected.Skip(10).Take(11));
        store.ReadBlocks(id, expected[^5].Line).Should().Equal(expected.TakeLast(5));
    }

    [Fact]
    public void Programs_are_kept_apart_and_diagnostics_are_stored()
    {
        var bad = Path.Combine(_temp.Path, "bad.nc");
        File.WriteAllText(bad, "O1\nG01 X1\nG05 Y-\n");
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "p.db"));
        var (demoId, _) = store.Import(Demo, MachineProfile.Default);
        var (badId, summary) = store.Import(bad, MachineProfile.Default);
        summary.Errors.Should().Be(3);
        store.GetDiagnostics(badId).Select(d => (d.Code, d.Line, d.Column)).Should().Equal(
            (DiagnosticCodes.FeedMoveWithoutFeed, 2, 1), (DiagnosticCodes.MalformedNumber, 3, 5), (DiagnosticCodes.UnknownGCode, 3, 1));
        store.GetDiagnostics(demoId).Should().BeEmpty();
        store.ReadBlocks(badId).Select(b => b.Line).Should().Equal(2, 3);
        store.ListPrograms().Select(p => p.Id).Should().Equal(badId, demoId);

        store.DeleteProgram(badId);
        store.GetProgram(badId).Should().BeNull();
        store.ReadBlocks(badId).Should().BeEmpty();
        store.ReadBlocks(demoId).Should().NotBeEmpty();
    }

    [Fact]
    public void An_unfinished_import_leaves_nothing_behind()
    {
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "p.db"));
        long id;
        using (var writer = store.BeginProgram("x.nc", 10, "default-mill"))
        {
            id = writer.ProgramId;
            writer.Add(new DecodedBlock { Line = 1, Modal = new ModalState() });
        }

        store.GetProgram(id).Should().BeNull();
        store.ReadBlocks(id).Should().BeEmpty();

        using var cts = new CancellationTokenSource();
        cts.Cancel();
        var act = () => store.Import(Demo, MachineProfile.Default, cancellationToken: cts.Token);
        act.Should().Throw<OperationCanceledException>();
        store.ListPrograms().Should().BeEmpty();
    }

    [Fact]
    public void Every_profiles_modal_groups_read_back_without_loss()
    {
        var program = Path.Combine(_temp.Path, "groups.nc");
        File.WriteAllText(program, "%\nO1\nG90 G54 G64 G50 G17 G40 G80 G94 G91.1 G49\nG21 T1 M06\nG43 H1 Z10 M08\nG98 G81 X1 Y1 Z-1 R2 F100\nX2\nG80\nG00 Z10 M09\nM30\n%\n");
        foreach (var name in MachineProfile.BuiltInNames)
        {
            var profile = MachineProfile.Named(name)!;
            var expected = new List<DecodedBlock>();
            new Checker(profile).CheckFile(program, _ => { }, expected.Add);
            using var store = ProgramStore.Open(Path.Combine(_temp.Path, name + ".db"));
            var (id, _) = store.Import(program, profile);
            store.ReadBlocks(id).Should().Equal(expected, name);
            store.GroupsOf(id).GNames.Should().Equal(profile.GGroups.Select(g => g.Name));
            store.GroupsOf(id).MNames.Should().Equal(profile.MGroups.Select(g => g.Name));
        }

        using var check = ProgramStore.Open(Path.Combine(_temp.Path, "fanuc-mill.db"));
        using var cmd = new Microsoft.Data.Sqlite.SqliteConnection($"Data Source={check.Path}");
        cmd.Open();
        using var q = cmd.CreateCommand();
        q.CommandText = "SELECT b.GI, s.more FROM blocks b JOIN group_states s ON s.program_id = b.program_id AND s.id = b.group_state WHERE b.Lines = 6";
        using (var c = cmd.CreateCommand())
        {
            c.CommandText = "SELECT COUNT(*), (SELECT COUNT(*) FROM blocks) FROM group_states";
            using var counts = c.ExecuteReader();
            counts.Read().Should().BeTrue();
            counts.GetInt64(0).Should().BeLessThan(counts.GetInt64(1), "a state is stored once, however many blocks share it");
        }

        using var r = q.ExecuteReader();
        r.Read().Should().BeTrue();
        (r.GetDouble(0), r.GetString(1)).Should().Be((81.0, "{\"G\":[94,98,64,50,69,15,50.1,67,97,23,91.1],\"M\":[null,null,null,null,null,null,null,null,null,null]}"),
            "the ninth group is in its column and the rest, in profile order, beside it");
    }

    [Fact]
    public void A_store_from_before_named_groups_gets_the_new_columns_and_its_programs_read_as_the_papers()
    {
        var path = Path.Combine(_temp.Path, "old.db");
        using (var old = new Microsoft.Data.Sqlite.SqliteConnection($"Data Source={path};Pooling=False"))
        {
            old.Open();
            using var cmd = old.CreateCommand();
            cmd.CommandText = """
                CREATE TABLE programs (id INTEGER PRIMARY KEY, path TEXT NOT NULL, size INTEGER NOT NULL, sha256 TEXT NOT NULL,
                    lines INTEGER NOT NULL, blocks INTEGER NOT NULL, errors INTEGER NOT NULL, warnings INTEGER NOT NULL,
                    estimated_seconds REAL NOT NULL, profile TEXT NOT NULL, check_summary TEXT NOT NULL, created TEXT NOT NULL);
                CREATE TABLE blocks (key INTEGER PRIMARY KEY, program_id INTEGER NOT NULL, Lines INTEGER NOT NULL, byte_offset INTEGER NOT NULL,
                    N REAL, block_delete INTEGER NOT NULL, GA REAL, GB REAL, GC REAL, GD REAL, GE REAL, GF REAL, GG REAL, GH REAL, GI REAL,
                    MA REAL, MB REAL, MC REAL, X REAL, Y REAL, Z REAL, I REAL, J REAL, K REAL, R REAL, F REAL, S REAL, T REAL, H REAL, D REAL,
                    P REAL, motion INTEGER NOT NULL, start_x REAL, start_y REAL, start_z REAL, end_x REAL, end_y REAL, end_z REAL,
                    center_x REAL, center_y REAL, center_z REAL, length REAL, duration REAL,
                    modal_t INTEGER, modal_h INTEGER, modal_d INTEGER, modal_s REAL, modal_f REAL);
                INSERT INTO programs VALUES (1, 'a.nc', 10, 'x', 1, 1, 0, 0, 0, 'default-mill', '0 errors, 0 warnings, 1 blocks', '2026-01-01T00:00:00Z');
                INSERT INTO blocks VALUES (4294967297, 1, 1, 0, NULL, 0, 1, 20, 91, 54, 18, 49, NULL, 40, NULL, NULL, 3, 8,
                    1, NULL, NULL, NULL, NULL, NULL, NULL, 100, NULL, NULL, NULL, NULL, NULL, 2, 0, 0, 0, 1, 0, 0, NULL, NULL, NULL, 1, 0.6,
                    0, 0, 0, 0, 100);
                """;
            cmd.ExecuteNonQuery();
        }

        using var store = ProgramStore.Open(path);
        var block = store.GetBlockAtLine(1, 1)!;
        block.Modal.G.Should().HaveCount(9);
        (block.Modal.Units, block.Modal.Plane, block.Modal.Absolute, block.Modal.Spindle, block.Modal.Coolant).Should().Be(
            (LengthUnits.Inches, 18, false, 3, 8));
        var (id, _) = store.Import(Demo, MachineProfile.Default);
        store.ReadBlocks(id).Should().Equal(Interpret(Demo), "new programs go into the migrated store whole");
    }
}
