using BenchmarkDotNet.Attributes;
using PmacStream.Benchmarks.Generators;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.Benchmarks.GCode;

/// <summary>
/// In-process throughput of the G-code pipeline on the surfacing program (100,000 lines held in memory, so disk
/// speed is out of the picture): lexing only, the full one-pass check, and check plus SQLite store.
/// Run: <c>dotnet run -c Release --project bench/PmacStream.Benchmarks -- --filter *CheckBenchmarks*</c>.
/// The whole-process numbers (peak RSS, rs274 comparison) come from <c>bench/scripts/check-bench.sh</c>.
/// </summary>
[MemoryDiagnoser]
public class CheckBenchmarks
{
    private const int Lines = 100_000;
    private byte[] _program = [];
    private string _dbDir = string.Empty;

    [GlobalSetup]
    public void Setup()
    {
        using var ms = new MemoryStream();
        SurfacingGenerator.Write(ms, Lines);
        _program = ms.ToArray();
        _dbDir = Directory.CreateTempSubdirectory("pmacstream-bench-").FullName;
    }

    [GlobalCleanup]
    public void Cleanup()
    {
        Microsoft.Data.Sqlite.SqliteConnection.ClearAllPools();
        Directory.Delete(_dbDir, true);
    }

    [Benchmark(Description = "lex 100k lines")]
    public int Lex()
    {
        var words = 0;
        using var reader = new GCodeReader(new MemoryStream(_program));
        while (reader.Read())
        {
            words += reader.Current.Words.Count;
        }

        return words;
    }

    [Benchmark(Description = "check 100k lines")]
    public long Check() => new Checker(MachineProfile.Default).Check(new MemoryStream(_program), "surf", _ => { }).Blocks;

    [Benchmark(Description = "check + interpret records 100k lines")]
    public long CheckWithBlocks()
    {
        long n = 0;
        new Checker(MachineProfile.Default).Check(new MemoryStream(_program), "surf", _ => { }, _ => n++);
        return n;
    }

    [Benchmark(Description = "check --db 100k lines")]
    public long CheckIntoStore()
    {
        var path = Path.Combine(_dbDir, Guid.NewGuid().ToString("N") + ".db");
        var file = Path.Combine(_dbDir, "surf.nc");
        if (!File.Exists(file))
        {
            File.WriteAllBytes(file, _program);
        }

        using var store = ProgramStore.Open(path);
        return store.Import(file, MachineProfile.Default).Summary.Blocks;
    }
}
