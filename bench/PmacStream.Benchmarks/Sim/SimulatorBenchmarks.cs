using BenchmarkDotNet.Attributes;
using PmacStream.Sim;

namespace PmacStream.Benchmarks.Sim;

/// <summary>
/// The simulator's own speed in instant mode: how many streamed G-code style moves per second it parses, stores,
/// calculates and executes. Moves/s = <see cref="Moves"/> / mean time.
/// </summary>
[MemoryDiagnoser]
public class SimulatorBenchmarks
{
    public const int Moves = 10_000;

    private readonly string[] _lines = new string[Moves];
    private PmacSimulator _sim = null!;
    private SimPort _port = null!;

    [GlobalSetup]
    public void Setup()
    {
        for (var i = 0; i < Moves; i++)
        {
            var cmd = (i % 4) switch { 0 or 1 => "G01", 2 => "G02", _ => "G03" };
            var x = 10 + (i % 2 == 0 ? 5 : -5);
            _lines[i] = i % 4 is 2 or 3
                ? $"M0=={i + 1} {cmd} X{x} Y10 I{(i % 4 == 2 ? 5 : -5)} J0 F(P500)"
                : $"M0=={i + 1} {cmd} X{x} Y10 F(P500)";
        }
    }

    [IterationSetup(Target = nameof(ExecuteInstant))]
    public void Download()
    {
        NewSimulator();
        foreach (var l in _lines)
        {
            _port.Execute(l);
        }

        _port.Execute("CLOSE");
    }

    /// <summary>Parse + store 10k lines into the rotary buffer (the host's download path).</summary>
    [Benchmark]
    public int DownloadLines()
    {
        NewSimulator();
        foreach (var l in _lines)
        {
            _port.Execute(l);
        }

        _port.Execute("CLOSE");
        return _sim.RotaryLinesAhead();
    }

    /// <summary>Calculate + execute 10k moves (library calls, arcs, sync M0) on the virtual clock.</summary>
    [Benchmark]
    public long ExecuteInstant()
    {
        _port.Execute("&1 B0 R");
        _sim.RunUntilIdle();
        return _sim.Counters.MovesExecuted;
    }

    private void NewSimulator()
    {
        _sim?.Dispose();
        _sim = new PmacSimulator(new SimOptions { DefaultRotWords = 10_000_000 });
        _port = _sim.OpenPort("bench");
        foreach (var l in new[]
        {
            "OPEN PROG 1000 CLEAR", "N0 RAPID RET", "N1000 LINEAR RET", "N2000 CIRCLE1 RET", "N3000 CIRCLE2 RET", "CLOSE",
            "P500=3000", "&1 B0 OPEN ROT", "G01 X10 Y10 F(P500)",
        })
        {
            _port.Execute(l);
        }
    }
}
