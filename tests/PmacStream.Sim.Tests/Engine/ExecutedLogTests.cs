using System.Net;
using PmacStream.Pmac;
using PmacStream.Sim.Servers;

namespace PmacStream.Sim.Tests.Engine;

/// <summary>
/// The executed-move log without memory that grows with the program: streamed to disk as moves finish, and checked
/// against the program's blocks as they finish.
/// </summary>
public sealed class ExecutedLogTests : IDisposable
{
    private readonly TestFolder _folder = new("executed");

    private string _dir => _folder.Path;

    public void Dispose() => _folder.Dispose();

    private static void RunMoves(SimHarness h, params int[] lines)
    {
        h.Download(["&1 B0", "OPEN ROT", .. lines.Select((l, i) => $"M0=={l} LINEAR X{i + 1} F6000"), "CLOSE"]);
        h.Ok("&1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(5));
    }

    [Fact]
    public void A_simulator_that_does_not_retain_moves_keeps_none_and_counts_them_all()
    {
        using var h = new SimHarness(new SimOptions { RetainExecutedMoves = false, RotaryEndBehaviour = RotaryEndBehaviour.EndWhenClosed });
        var check = new ExecutedLineCheck([10, 11, 12]).Attach(h.Sim);
        var log = new ExecutedLogWriter(Path.Combine(_dir, "executed.csv")).Attach(h.Sim);

        RunMoves(h, 10, 11, 12);
        log.Complete();

        h.Sim.ExecutedMoves.Should().BeEmpty("nothing is kept in memory");
        h.Sim.Counters.MovesExecuted.Should().Be(3);
        check.Finish().Should().Be(new ExecutedLineResult(3, 3, null));
        File.ReadAllLines(log.Path).Should().HaveCount(4).And.StartWith(ExecutedLogWriter.Header);
        File.ReadAllLines(log.Path).Skip(1).Select(l => l.Split(',')[0] + ":" + l.Split(',')[1]).Should().Equal("1:10", "2:11", "3:12");
        File.Exists(log.Path + ".tmp").Should().BeFalse();
    }

    [Fact]
    public void A_one_move_block_run_twice_in_a_row_is_a_repeat_the_checks_and_the_log_show()
    {
        using var h = new SimHarness(new SimOptions { RotaryEndBehaviour = RotaryEndBehaviour.EndWhenClosed });
        var check = new ExecutedLineCheck([1, 2, 3]).Attach(h.Sim);
        var log = new ExecutedLogWriter(Path.Combine(_dir, "repeat.csv")).Attach(h.Sim);

        // Block 2 (one move, its synchronous tracking assignment) sent twice, then a two-move block 3 (a DWELL after
        // its move carries no assignment: the same block).
        h.Download("&1 B0", "OPEN ROT", "M0==1 LINEAR X1 F6000", "M0==2 X2", "M0==2 X2", "M0==3 X3", "DWELL 10", "CLOSE");
        h.Ok("&1 R");
        h.Sim.RunUntilIdle(TimeSpan.FromMinutes(1));
        log.Complete();

        h.Sim.ExecutedMoves.Select(m => m.BlockStart).Should().Equal(true, true, true, true, false);
        MoveLines.Blocks(h.Sim.ExecutedMoves).Should().Equal(1, 2, 2, 3);
        var result = check.Finish();
        result.Exact.Should().BeFalse("line 2 ran twice");
        result.FirstBreak.Should().Be("block order broken at block 3: expected line 3, executed line 2");
        var rows = File.ReadAllLines(log.Path);
        rows[0].Should().Be("sequence,line,start_s,end_s,x,y,z,a,b,c,kind,block", "the header names every column");
        rows.Skip(1).Select(l => l.Split(',')[1] + ":" + l.Split(',')[11]).Should().Equal("1:1", "2:1", "2:1", "3:1", "3:0");
    }

    [Fact]
    public void The_log_grows_on_disk_while_moves_run()
    {
        using var h = new SimHarness(new SimOptions { RetainExecutedMoves = false });
        using var log = new ExecutedLogWriter(Path.Combine(_dir, "growing.csv")).Attach(h.Sim);
        RunMoves(h, Enumerable.Range(1, 2000).ToArray());

        log.Rows.Should().Be(2000);
        File.Exists(log.Path).Should().BeFalse("moved into place when complete");
        File.Exists(log.Path + ".tmp").Should().BeTrue("rows so far are on disk, for a host killed meanwhile");
    }

    [Fact]
    public async Task A_later_move_waits_while_an_earlier_one_is_still_being_delivered()
    {
        // Two threads advance the clock (in a server: the clock thread, and a command's thread settling its
        // instant). The first is held inside its delivery of move 1 while the second finishes move 2.
        using var h = new SimHarness();
        RunMovesLater(h);
        var seen = new List<long>();
        using var entered = new ManualResetEventSlim();
        using var gate = new ManualResetEventSlim();
        h.Sim.MoveExecuted += m =>
        {
            if (m.Sequence == 1)
            {
                entered.Set();
                gate.Wait(TimeSpan.FromSeconds(5));
            }

            lock (seen)
            {
                seen.Add(m.Sequence);
            }
        };

        var first = Task.Run(() => h.Sim.Advance(TimeSpan.FromSeconds(1.5)));
        entered.Wait(TimeSpan.FromSeconds(5)).Should().BeTrue();
        var second = Task.Run(() => h.Sim.Advance(TimeSpan.FromSeconds(1)));
        await Task.Delay(300);
        lock (seen)
        {
            seen.Should().BeEmpty("move 2 must not overtake move 1, still being delivered");
        }

        gate.Set();
        await Task.WhenAll(first, second);
        seen.Should().Equal(1, 2);
    }

    private static void RunMovesLater(SimHarness h)
    {
        h.Download("&1 B0", "OPEN ROT", "M0==1 LINEAR X10 F600", "M0==2 X20", "CLOSE");
        h.Ok("&1 R");
    }

    [Fact]
    public void A_block_the_host_expands_fires_its_assignment_on_each_line_and_counts_once_until_it_fires_again()
    {
        // Line 9, a reference return, is two controller lines, each with M0==9.
        var expanded = new Dictionary<int, int> { [9] = 2 };
        var once = new ExecutedLineCheck([9, 13], expandedBlocks: expanded);
        foreach (var (line, fired) in new[] { (9, true), (9, true), (13, true), (13, false) })
        {
            once.Add(line, fired);
        }

        once.Finish().Should().Be(new ExecutedLineResult(2, 2, null));
        ExecutedLineCheck.Blocks([(9, true), (9, true), (9, true), (9, true), (13, true)], expanded).Should().Equal(9, 9, 13);
        ExecutedLineCheck.Blocks([(9, true), (9, true), (13, true)]).Should().Equal(new[] { 9, 9, 13 }, "without the program's expansions each assignment is a block");
    }

    [Theory]
    [InlineData(new[] { 1, 1, 2, 0, 3 }, 3, null)]
    [InlineData(new[] { 1, 2, 2, 1, 2, 3 }, 5, "block order broken at block 3: expected line 3, executed line 1")]
    [InlineData(new[] { 1, 3 }, 2, "block order broken at block 2: expected line 2, executed line 3")]
    [InlineData(new[] { 1, 2 }, 2, null)]
    [InlineData(new[] { 1, 2, 3, 4 }, 4, "block 4 (line 4) executed after the program's last block")]
    public void The_check_counts_a_block_s_unmarked_moves_once_and_finds_repeats_skips_and_extras(int[] executed, int blocks, string? broken)
    {
        var check = new ExecutedLineCheck([1, 2, 3]);
        foreach (var line in executed)
        {
            check.Add(line, blockStart: false);
        }

        var result = check.Finish();
        result.Executed.Should().Be(blocks);
        result.Expected.Should().Be(3);
        result.FirstBreak.Should().Be(broken);
        result.Exact.Should().Be(broken is null && blocks == 3);
    }

    [Fact]
    public void A_start_from_a_line_leaves_out_the_preamble_and_earlier_lines()
    {
        var check = new ExecutedLineCheck([20, 21], fromLine: 20);
        foreach (var line in new[] { 0, 5, 20, 21 })
        {
            check.Add(line, blockStart: true);
        }

        check.Finish().Exact.Should().BeTrue();
    }

    [Fact]
    public async Task A_host_streams_its_log_and_keeps_no_moves_when_told_not_to()
    {
        var path = Path.Combine(_dir, "host.csv");
        await using var host = new SimHost(new SimHostOptions
        {
            Simulator = new SimOptions { Speed = SimSpeed.Instant, RetainExecutedMoves = false },
            TcpEndPoint = new IPEndPoint(IPAddress.Loopback, 0),
            ExecutedLogPath = path,
        });
        host.Start();
        await using (var eth = new EthernetConnection(new EthernetOptions { Port = host.TcpEndPoint!.Port, Timeout = TimeSpan.FromSeconds(5) }))
        {
            await eth.DownloadAsync(["&1 B0", "OPEN ROT", "M0==7 LINEAR X10 F600", "M0==8 X20", "CLOSE"]);
            await eth.GetResponseAsync("&1 R");
            for (var i = 0; i < 500 && host.Simulator.Counters.MovesExecuted < 2; i++)
            {
                await Task.Delay(10);
            }
        }

        File.Exists(path + ".tmp").Should().BeTrue("written while it runs");
        (await host.StopAsync()).MovesExecuted.Should().Be(2);
        host.Simulator.ExecutedMoves.Should().BeEmpty();
        File.ReadAllLines(path).Skip(1).Select(l => l.Split(',')[1]).Should().Equal("7", "8");
    }
}
