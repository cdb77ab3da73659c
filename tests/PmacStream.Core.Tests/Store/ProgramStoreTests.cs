using PmacStream.Core.Tests.GCode;
using PmacStream.GCode;
using PmacStream.Program.Store;

namespace PmacStream.Core.Tests.Store;

public sealed class ProgramStoreTests : IDisposable
{
    private readonly string _dir = Directory.CreateTempSubdirectory("pmacstream-store-").FullName;

    private string Demo => RepoRoot.DemoProgram;

    public void Dispose()
    {
        Microsoft.Data.Sqlite.SqliteConnection.ClearAllPools();
        Directory.Delete(_dir, true);
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
        using var store = ProgramStore.Open(Path.Combine(_dir, "p.db"));
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
        using var store = ProgramStore.Open(Path.Combine(_dir, "p.db"));
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
        var bad = Path.Combine(_dir, "bad.nc");
        File.WriteAllText(bad, "O1\nG01 X1\nG05 Y-\n");
        using var store = ProgramStore.Open(Path.Combine(_dir, "p.db"));
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
        using var store = ProgramStore.Open(Path.Combine(_dir, "p.db"));
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
}
