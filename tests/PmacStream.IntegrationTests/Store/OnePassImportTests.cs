using System.Data.Common;
using System.Globalization;
using System.Text;
using Microsoft.Data.Sqlite;
using Npgsql;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// A split that stores the revision in the same pass (<see cref="Splitter.SplitAndImport"/>, what <c>stream FILE</c>
/// does for a file not yet stored) writes exactly the rows a separate <c>programs import</c> writes (every column of
/// every table of the revision, on both engines) and exactly the chunk files a plain split writes: the corpus's CAM
/// programs and programs made to reach every part of the record (compensated inside corners with plunges, arcs,
/// cycles, shifts, numbered and unnumbered blocks, errors, a UTF-16 file).
/// </summary>
public sealed class OnePassImportTests : IDisposable
{
    private readonly TestFolder _folder = new("one-pass");

    public static TheoryData<string> Engines => new() { "sqlite", "postgres" };

    public void Dispose() => _folder.Dispose();

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void Every_corpus_program_stores_the_rows_of_a_separate_import_and_splits_to_the_same_chunks(string engine)
    {
        var location = Location(engine);
        var checkedPrograms = 0;
        foreach (var file in Requires.Corpus())
        {
            Same(location, Copy(file), force: true);
            checkedPrograms++;
        }

        checkedPrograms.Should().BeGreaterThanOrEqualTo(12);
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void Made_programs_store_the_rows_of_a_separate_import(string engine)
    {
        var location = Location(engine);
        var pockets = Same(location, Write("pockets.nc", Pockets), WithRadius(), force: false);
        pockets.Errors.Should().Be(0);
        pockets.Blocks.Should().BeGreaterThan(30);
        Same(location, Write("numbered.nc", Numbered), force: false).Warnings.Should().BeGreaterThan(0, "W002 on the unnumbered blocks, held until the program numbered one");

        // Refused by the split (errors): the revision is stored with them all the same, before the refusal.
        var errors = Same(location, Write("errors.nc", Errors), force: false);
        errors.Errors.Should().BeGreaterThan(0);

        // o-words: the blocks stored are the expansion's, as the split cuts them, with the expansion's source map.
        var loop = Same(location, Write("loop.ngc", Loop), MachineProfile.Named("linuxcnc-mill")!, force: false);
        loop.Errors.Should().Be(0);
        loop.Blocks.Should().BeGreaterThanOrEqualTo(5, "the loop's body is stored once for each of its three runs");
        using (var store = ProgramStores.Open(location))
        {
            store.ReadExpansionMap(loop.Id).Should().NotBeNull("the expansion's map is stored with the revision");
        }

        var utf16 = Path.Combine(_folder.Path, $"utf16-{Guid.NewGuid():N}.nc");
        File.WriteAllText(utf16, $"({Guid.NewGuid():N})\nG21 G90\nG0 X1\nM30\n", new UnicodeEncoding(false, true));
        Same(location, utf16, force: false).Errors.Should().Be(1, "one error for the UTF-16 file, and the check ends there");
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public void A_block_delete_block_under_block_delete_gives_the_import_up_and_the_split_stays_whole(string engine)
    {
        var location = Location(engine);
        var file = Write("slash.nc", "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F300\n/G1 X50\nG1 X10 Y10\nG0 Z5\nM30\n");
        var plain = Splitter.Split(file, Options(_folder.NewFolder("plain"), force: false));
        int before;
        using (var store = ProgramStores.Open(location))
        {
            before = store.ListRevisions().Count;
            using var import = RevisionImport.Begin(store, file, new FileInfo(file).Length, MachineProfile.Default);
            var split = Splitter.SplitAndImport(file, Options(_folder.NewFolder("one-pass"), force: false), import);
            import.Result.Should().BeNull("the split skips line 4, the store decodes it: one check cannot give both");
            SameFiles(plain.OutputDirectory, split.OutputDirectory);
        }

        using (var store = ProgramStores.Open(location))
        {
            store.ListRevisions().Should().HaveCount(before, "nothing of the import given up is kept");
        }

        // Block delete off: the split decodes every block too, and the one pass stores it.
        var whole = Same(location, Write("slash-off.nc", "G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F300\n/G1 X50\nG1 X10 Y10\nG0 Z5\nM30\n"), force: false, blockDelete: false);
        whole.Blocks.Should().Be(7, "every block, the block-delete one too");
    }

    [SkippableTheory]
    [MemberData(nameof(Engines))]
    public async Task Stream_file_imports_in_the_split_pass_and_finds_it_the_second_time(string engine)
    {
        var location = Location(engine);
        var file = Write("part.nc", Pockets);
        var service = new JobService(new JobServiceOptions { Store = location });
        var profile = WithRadius();
        var first = await service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Import = true, Profile = profile, OutDir = _folder.NewFolder("chunks") });
        service.ImportedInSplitPass.Should().Be(1, "the file was read once: checked, stored and split together");
        service.PreparationsStored.Should().Be(1);
        using (var store = ProgramStores.Open(location))
        {
            var info = store.GetProgram(first.ProgramId!.Value)!;
            info.Sha256.Should().Be(first.Program.Manifest.SourceSha256, "the revision and the manifest hash the same read");
            info.Size.Should().Be(first.Program.Manifest.SourceSize);
            store.ReadStoredBlocks(info.Id).Count().Should().Be((int)info.Blocks, "every block decoded in the pass is stored");
        }

        var again = await service.PrepareAsync(new PrepareRequest(file, RunSettings.Default) { Import = true, Profile = profile, OutDir = _folder.NewFolder("chunks") });
        again.ProgramId.Should().Be(first.ProgramId);
        service.ImportedInSplitPass.Should().Be(1, "found by its SHA-256, not read again");
        service.PreparationsReused.Should().Be(1);

        // A program with o-words: imported in the split's pass too; its preparation (which reads other files and the
        // persistent variables) stays beside the file.
        var loop = await service.PrepareAsync(new PrepareRequest(Write("loop.ngc", Loop), RunSettings.Default) { Import = true, Profile = MachineProfile.Named("linuxcnc-mill")!, OutDir = _folder.NewFolder("chunks") });
        loop.ProgramId.Should().NotBeNull();
        service.ImportedInSplitPass.Should().Be(2);
        service.PreparationsStored.Should().Be(1, "an expanded program's preparation is not stored");
    }

    /// <summary>
    /// Splits <paramref name="file"/> plainly and with the import, compares the chunk folders byte for byte, reads every
    /// row the import stored, deletes the revision, imports the file separately, and compares every row.
    /// </summary>
    private static ProgramInfo Same(StoreLocation location, string file, bool force, bool blockDelete = true) =>
        Same(location, file, MachineProfile.Default, force, blockDelete);

    private static ProgramInfo Same(StoreLocation location, string file, MachineProfile profile, bool force, bool blockDelete = true)
    {
        var plainDir = Path.Combine(Path.GetDirectoryName(file)!, "plain");
        var onePassDir = Path.Combine(Path.GetDirectoryName(file)!, "one-pass");
        SplitResult? plain = null;
        SplitException? plainRefusal = null;
        try
        {
            plain = Splitter.Split(file, Options(profile, plainDir, force, blockDelete));
        }
        catch (SplitException e)
        {
            plainRefusal = e;
        }

        using var store = ProgramStores.Open(location);
        long id;
        using (var import = RevisionImport.Begin(store, file, new FileInfo(file).Length, profile))
        {
            var split = () => Splitter.SplitAndImport(file, Options(profile, onePassDir, force, blockDelete), import);
            if (plainRefusal is null)
            {
                var together = split();
                SameFiles(plain!.OutputDirectory, together.OutputDirectory);
                together.LaneLines.Should().Be(plain.LaneLines, "the lines a plain split sends as the lane's text go the same way, interpreted in full");
            }
            else
            {
                split.Should().Throw<SplitException>().Which.ErrorCount.Should().Be(plainRefusal.ErrorCount, Path.GetFileName(file));
            }

            import.Result.Should().NotBeNull($"{Path.GetFileName(file)} is stored in the split's pass");
            import.Result!.Existing.Should().BeFalse();
            id = import.Result.Id;
        }

        var onePass = Rows(location, id);
        var info = store.GetProgram(id)!;
        store.DeleteProgram(id);
        var separate = store.ImportRevision(file, profile);
        var rows = Rows(location, separate.Id);
        foreach (var (table, list) in onePass)
        {
            rows[table].Should().Equal(list, $"{Path.GetFileName(file)}: table {table}, one pass against a separate import");
        }

        onePass["blocks"].Count.Should().Be((int)info.Blocks);
        return info with { Id = separate.Id };
    }

    private static SplitOptions Options(string outDir, bool force, bool blockDelete = true) => Options(MachineProfile.Default, outDir, force, blockDelete);

    private static SplitOptions Options(MachineProfile profile, string outDir, bool force, bool blockDelete = true) =>
        RunSettings.Default.ToSplitOptions(profile, outDir, force) with { BlockDelete = blockDelete };

    /// <summary>The default profile with tool 1's radius, for G41/G42.</summary>
    private static MachineProfile WithRadius()
    {
        var json = System.Text.Json.Nodes.JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["toolRadii"] = new System.Text.Json.Nodes.JsonObject { ["1"] = 2 };
        return MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+radius");
    }

    private static void SameFiles(string expected, string actual)
    {
        var names = Directory.GetFiles(expected).Select(Path.GetFileName).Order(StringComparer.Ordinal).ToList();
        Directory.GetFiles(actual).Select(Path.GetFileName).Order(StringComparer.Ordinal).Should().Equal(names);
        foreach (var name in names)
        {
            File.ReadAllBytes(Path.Combine(actual, name!)).Should().Equal(File.ReadAllBytes(Path.Combine(expected, name!)), $"{name} is the plain split's");
        }
    }

    /// <summary>Every row of the revision in every table (its own id, keys and creation time left out), each table's rows sorted.</summary>
    private static Dictionary<string, List<string>> Rows(StoreLocation location, long id)
    {
        var postgres = location.Engine == StoreEngine.Postgres;
        using DbConnection connection = postgres ? new NpgsqlConnection(location.Target) : new SqliteConnection($"Data Source={location.Target}");
        connection.Open();
        var tables = new Dictionary<string, List<string>>();
        foreach (var table in new[] { "programs", "blocks", "diagnostics", "group_states", "exec_states", "cycle_holes", "program_source", "expansion_maps" })
        {
            using var cmd = connection.CreateCommand();
            cmd.CommandText = $"SELECT * FROM {table} WHERE {(table == "programs" ? "id" : "program_id")} = @p";
            var p = cmd.CreateParameter();
            p.ParameterName = postgres ? "p" : "@p";
            p.Value = id;
            cmd.Parameters.Add(p);
            var rows = new List<string>();
            using (var r = cmd.ExecuteReader())
            {
                while (r.Read())
                {
                    var row = new StringBuilder();
                    for (var i = 0; i < r.FieldCount; i++)
                    {
                        var name = r.GetName(i);
                        if (name is "id" or "program_id" or "key" or "created" && !(table == "group_states" && name == "id"))
                        {
                            continue;
                        }

                        row.Append(name).Append('=').Append(Text(r.GetValue(i))).Append(';');
                    }

                    rows.Add(row.ToString());
                }
            }

            rows.Sort(StringComparer.Ordinal);
            tables[table] = rows;
        }

        return tables;
    }

    private static string Text(object value) => value switch
    {
        DBNull => "null",
        double d => d.ToString("R", CultureInfo.InvariantCulture),
        byte[] bytes => Convert.ToHexString(System.Security.Cryptography.SHA256.HashData(bytes)),
        IFormattable f => f.ToString(null, CultureInfo.InvariantCulture),
        _ => value.ToString() ?? "null",
    };

    private string Copy(string file)
    {
        // A line of its own on top: the store keys revisions by content, and a shared PostgreSQL store keeps them between runs.
        var copy = Path.Combine(_folder.NewFolder("src"), Path.GetFileName(file));
        File.WriteAllBytes(copy, [.. Encoding.ASCII.GetBytes($"({Guid.NewGuid():N})\n"), .. File.ReadAllBytes(file)]);
        return copy;
    }

    private string Write(string name, string text)
    {
        var path = Path.Combine(_folder.NewFolder("src"), name);
        File.WriteAllText(path, $"({Guid.NewGuid():N})\n{text}", new UTF8Encoding(false));
        return path;
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

    private const string Pockets = """
        G21 G90 G17 G40 G49 G80
        G54
        T1 M6
        G43 H1
        S12000 M3
        M8
        G0 X-10 Y-10 Z5
        G1 Z-1 F300
        G41 D1 X0 Y0 F600
        G1 X40
        G0 Z2
        G1 Z-1.5 F200
        G1 Y30 F600
        G3 X30 Y40 R10
        G1 X0
        G2 X-5 Y35 I0 J-5
        G1 Y0
        G40 G1 X-10 Y-10
        G0 Z5
        G55
        G0 X10 Y10
        G81 X10 Y10 Z-3 R2 F150
        X20
        X30 Y20
        G80
        G83 X5 Y5 Z-8 R2 Q2 F120
        G80
        G91 G1 X5 Y5 F500
        G90 G4 P0.5
        G52 X5 Y5
        G0 X0 Y0
        G52 X0 Y0
        G0 X0 Y0 Z0
        G17 G2 X20 Y0 I10 J0 F400
        G18 G2 X30 Z0 I5 K0
        G17 M9
        M5
        M30
        """;

    private const string Loop = """
        G21 G90 G17
        #1 = 0
        o100 while [#1 LT 3]
        G01 X[#1] Y1 F600
        #1 = [#1 + 1]
        o100 endwhile
        M2
        """;

    private const string Numbered = """
        G21 G90
        G0 X0 Y0 Z5
        N10 G1 Z-1 F300
        N20 X10
        G1 Y10
        N30 G0 Z5
        M30
        """;

    private const string Errors = """
        G21 G90
        G0 X0 Y0 Z5
        G1 X10 F300 Q
        G2 X5
        G1 X1 Y1
        M30
        """;
}
