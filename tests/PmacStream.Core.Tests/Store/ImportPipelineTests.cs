using Microsoft.Data.Sqlite;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Core.Tests.Store;

/// <summary>The two-thread import (<see cref="ImportPipeline"/>): batch boundaries and failures on either side.</summary>
public sealed class ImportPipelineTests : IDisposable
{
    private readonly TestFolder _temp = new("pipeline");

    public void Dispose()
    {
        SqliteConnection.ClearAllPools();
        _temp.Dispose();
    }

    private string Program(int moves, int seed, string? extraAt = null, int extraLine = -1)
    {
        var rnd = new Random(seed);
        var sb = new System.Text.StringBuilder("%\nO0100\nN1 G21 G17 G90 G54\nN2 G01 F500\n");
        for (var i = 0; i < moves; i++)
        {
            if (i == extraLine && extraAt != null)
            {
                sb.Append(extraAt).Append('\n');
            }

            // Mixed blocks: moves, an occasional arc, comment-only and blank lines (no block, still a line).
            switch (rnd.Next(20))
            {
                case 0: sb.Append("(pass ").Append(i).Append(")\n"); break;
                case 1: sb.Append('\n'); break;
                case 2: sb.Append($"N{i + 3} G02 X{rnd.Next(100)} Y{rnd.Next(100)} R200\n"); break;
                default: sb.Append($"N{i + 3} G01 X{rnd.NextDouble() * 100:F4} Y{rnd.NextDouble() * 100:F4} Z{-rnd.NextDouble():F4}\n"); break;
            }
        }

        sb.Append("M30\n%\n");
        var path = Path.Combine(_temp.Path, $"p{seed}.nc");
        File.WriteAllText(path, sb.ToString());
        return path;
    }

    private static List<DecodedBlock> Interpret(string file)
    {
        var list = new List<DecodedBlock>();
        new Checker(MachineProfile.Default).CheckFile(file, _ => { }, list.Add);
        return list;
    }

    [Theory]
    [InlineData(0)]
    [InlineData(1)]
    [InlineData(ImportPipeline.BatchSize - 3)]
    [InlineData((ImportPipeline.BatchSize * 2) + 37)]
    [InlineData((ImportPipeline.BatchSize * (ImportPipeline.QueueDepth + 3)) + 5)]
    public void Every_block_round_trips_whatever_the_batch_boundaries(int moves)
    {
        var file = Program(moves, moves);
        var expected = Interpret(file);
        // Land exactly on a batch boundary too: the header blocks plus the moves are not a multiple of the batch.
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "s.db"));
        var (id, summary) = store.Import(file, MachineProfile.Default);
        summary.Blocks.Should().Be(expected.Count);
        var stored = store.ReadBlocks(id).ToList();
        stored.Should().HaveCount(expected.Count);
        for (var i = 0; i < stored.Count; i++)
        {
            stored[i].Should().Be(expected[i], $"block {i} (line {expected[i].Line})");
        }
    }

    [Fact]
    public void A_move_before_a_G41_inside_corner_is_stored_with_its_end_moved_back_across_batch_boundaries()
    {
        // A pocket cut round and round under G41 D1 (radius 5): every corner is an inside one, every block a move, so
        // each batch boundary falls between a move and the corner that moves its end back.
        var json = System.Text.Json.Nodes.JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["toolRadii"] = System.Text.Json.Nodes.JsonNode.Parse("""{ "1": 5 }""");
        var profile = MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+radii");
        var sb = new System.Text.StringBuilder("G21 G90 G17\nG00 X50. Y25. Z5.\nG01 Z-1. F100\nG41 D1 X50. Y0\n");
        for (var i = 0; i < 600; i++)
        {
            sb.Append("X100.\nY50.\nX0\nY0\n");
        }

        sb.Append("G40 X50. Y25.\nM30\n");
        var file = Path.Combine(_temp.Path, "pocket.nc");
        File.WriteAllText(file, sb.ToString());

        // Expected: the interpreter's ends, the move before each inside corner moved back (as the splitter sends it).
        var ends = new BlockEnds();
        var interp = new Interpreter(profile) { Canon = ends };
        foreach (var block in GCodeReader.ReadAll(file))
        {
            interp.Execute(block);
        }

        var expected = ends.Ends;

        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "s.db"));
        var (id, _) = store.Import(file, profile);
        var stored = store.ReadBlocks(id).ToList();
        stored.Should().HaveCountGreaterThan(2 * ImportPipeline.BatchSize);
        stored.Select(b => b.End).Should().Equal(expected);
        stored.Single(b => b.Line == 4).End.Should().Be(new Point3(55, 5, -1), "the entry ends where the offset paths cross, not at (55, 0)");
        stored.Where(b => b.Line > 4 && b.Motion == MotionKind.Linear).Should().OnlyContain(b => b.End.X == 5 || b.End.X == 95 || b.End.X == 50, "every corner of the pocket is 5 mm inside");
        stored.Single(b => b.Line == 5).Length.Should().BeApproximately(40, 1e-9, "(55, 5) to (95, 5): the length as it runs");
    }

    [Fact]
    public void Z_blocks_queued_behind_a_G41_move_are_stored_at_the_inside_corners_crossing_across_batch_boundaries()
    {
        // The pocket round and round with a plunge or a retract (and now and then a dwell) between every two XY moves:
        // queued behind the held move, they run at the crossing; batch boundaries fall inside the holds.
        var json = System.Text.Json.Nodes.JsonNode.Parse(MachineProfile.Default.ToJson())!.AsObject();
        json["toolRadii"] = System.Text.Json.Nodes.JsonNode.Parse("""{ "1": 5 }""");
        var profile = MachineProfile.Parse(json.ToJsonString(), "fanuc-mill+radii");
        var sb = new System.Text.StringBuilder("G21 G90 G17\nG00 X50. Y25. Z5.\nG01 Z-1. F100\nG41 D1 X50. Y0\n");
        for (var i = 0; i < 300; i++)
        {
            sb.Append("Z-2.\nX100.\nZ-1.\nY50.\nG04 X0.1\nZ-2.\nX0\nZ-1.\nY0\n");
        }

        sb.Append("G40 X50. Y25.\nM30\n");
        var file = Path.Combine(_temp.Path, "plunged.nc");
        File.WriteAllText(file, sb.ToString());

        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "s.db"));
        var (id, summary) = store.Import(file, profile);
        summary.Errors.Should().Be(0);
        var stored = store.ReadBlocks(id).ToList();
        stored.Should().HaveCountGreaterThan(2 * ImportPipeline.BatchSize);
        var comp = stored.Where(b => b.Line > 5 && b.Line < stored[^1].Line - 2 && b.Motion == MotionKind.Linear).ToList(); // the last Y0 before G40 is not moved
        static bool Near(double a, double b) => Math.Abs(a - b) < 1e-9;
        comp.Where(b => !((Near(b.End.X, 5) || Near(b.End.X, 95)) && (Near(b.End.Y, 5) || Near(b.End.Y, 45)))).Should().BeEmpty("every move under G41 ends at a corner of the offset pocket, the Z blocks too");
        comp.Where(b => b.Start.Z != b.End.Z && !(Near(b.Start.X, b.End.X) && Near(b.Start.Y, b.End.Y) && Near(b.Length, 1))).Should().BeEmpty("a plunge runs at the crossing, its own 1 mm");
        comp.Where(b => b.Start.Z == b.End.Z && !(Near(b.Length, 90) || Near(b.Length, 40))).Should().BeEmpty("the XY moves as they run: 90 and 40 mm between the crossings");
        comp.Count(b => b.Start.Z != b.End.Z).Should().Be(1199, "two plunges and two retracts a round, the first (line 5) checked below");
        stored.Single(b => b.Line == 4).End.Should().Be(new Point3(55, 5, -1), "the entry and the plunge after it end at the first crossing");
        stored.Single(b => b.Line == 5).End.Should().Be(new Point3(55, 5, -2));
    }

    [Fact]
    public void Exactly_one_full_batch_and_diagnostics_across_batches_are_stored()
    {
        // "O0100" alone is no block: 1 header block + (BatchSize - 2) moves + M30 = BatchSize blocks.
        var path = Path.Combine(_temp.Path, "exact.nc");
        var lines = new List<string> { "O0100", "N1 G21 G90 G01 F100" };
        for (var i = 0; i < ImportPipeline.BatchSize - 2; i++)
        {
            // Every 100th move has an unknown G code: diagnostics in many batches.
            lines.Add(i % 100 == 0 ? $"N{i + 2} G77 X{i}" : $"N{i + 2} G01 X{i}");
        }

        lines.Add("N9999 M30");
        File.WriteAllLines(path, lines);
        var seen = new List<Diagnostic>();
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "s.db"));
        var (id, summary) = store.Import(path, MachineProfile.Default, seen.Add);
        summary.Blocks.Should().Be(ImportPipeline.BatchSize);
        store.ReadBlocks(id).Count().Should().Be(ImportPipeline.BatchSize);
        seen.Select(d => d.Line).Should().BeInAscendingOrder();
        seen.Select(d => d.Code).Should().Equal(Enumerable.Repeat(DiagnosticCodes.UnknownGCode, 11));
        store.GetDiagnostics(id).Should().Equal(seen);
    }

    [Fact]
    public void A_store_failure_mid_import_stops_the_reader_and_rolls_back_everything()
    {
        var db = Path.Combine(_temp.Path, "s.db");
        var ok = Program(50, 7);
        var big = Program(ImportPipeline.BatchSize * 20, 8);
        using var store = ProgramStore.Open(db);
        var (keep, _) = store.Import(ok, MachineProfile.Default);

        // A trigger makes SQLite refuse one row deep inside the second program (after several batches).
        using (var c = new SqliteConnection($"Data Source={db};Pooling=False"))
        {
            c.Open();
            using var cmd = c.CreateCommand();
            cmd.CommandText = "CREATE TRIGGER refuse BEFORE INSERT ON blocks WHEN NEW.program_id > 1 AND NEW.Lines = 5000 " +
                              "BEGIN SELECT RAISE(ABORT, 'refused by test'); END;";
            cmd.ExecuteNonQuery();
        }

        var act = () => store.Import(big, MachineProfile.Default);
        act.Should().Throw<SqliteException>().WithMessage("*refused by test*");

        store.ListPrograms().Select(p => p.Id).Should().Equal(keep);
        using var check = new SqliteConnection($"Data Source={db};Pooling=False");
        check.Open();
        using var count = check.CreateCommand();
        count.CommandText = "SELECT COUNT(*) FROM blocks WHERE program_id <> $k";
        count.Parameters.AddWithValue("$k", keep);
        count.ExecuteScalar().Should().Be(0L);
        store.ReadBlocks(keep).Count().Should().Be((int)store.GetProgram(keep)!.Blocks);
    }

    [Fact]
    public void A_reader_failure_mid_import_rolls_back_and_surfaces_unwrapped()
    {
        var big = Program(ImportPipeline.BatchSize * 10, 9, extraAt: "G77", extraLine: ImportPipeline.BatchSize * 8);
        using var store = ProgramStore.Open(Path.Combine(_temp.Path, "s.db"));
        var act = () => store.Import(big, MachineProfile.Default, d => throw new InvalidOperationException($"stop at {d.Line}"));
        act.Should().Throw<InvalidOperationException>().WithMessage("stop at *");
        store.ListPrograms().Should().BeEmpty();

        using var cts = new CancellationTokenSource();
        var cancelAt = 0;
        var cancelled = () => store.Import(big, MachineProfile.Default, _ =>
        {
            cancelAt++;
            cts.Cancel();
        }, cts.Token);
        cancelled.Should().Throw<OperationCanceledException>();
        cancelAt.Should().BeInRange(1, 4, "the reader stops at the next line once cancelled (one line may carry several diagnostics)");
        store.ListPrograms().Should().BeEmpty();
    }

    /// <summary>
    /// Where every block left the machine, from the canonical calls: a block's position at its end, the move before an
    /// inside corner moved back to where the offset paths cross (<see cref="CanonBlock.AmendedEnd"/>).
    /// </summary>
    private sealed class BlockEnds : ICanonicalMoves
    {
        private int _lastMove = -1;
        private bool _moved;

        public List<Point3> Ends { get; } = [];

        public void StartBlock(in CanonStart start) => _moved = false;

        public void Step(in HostMove step)
        {
        }

        public void Motion(in CanonMotion motion) => _moved = motion.Kind is not MotionKind.Dwell;

        public void EndBlock(in CanonBlock block)
        {
            if (block.AmendedEnd is { } amended && _lastMove >= 0)
            {
                Ends[_lastMove] = amended;
            }

            Ends.Add(block.Position);
            _lastMove = _moved ? Ends.Count - 1 : _lastMove;
        }
    }
}
