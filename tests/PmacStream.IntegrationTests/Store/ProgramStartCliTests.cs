using System.Text;
using PmacStream.Cli;
using PmacStream.Cli.Commands;
using PmacStream.GCode;
using PmacStream.Preparation.Store;

namespace PmacStream.IntegrationTests.Store;

/// <summary>
/// `pmacstream programs start ID --from-line N [--reinterpret]` in process (<see cref="ProgramStartCommand.Run"/>): the
/// preamble of a start at a line of a stored revision, from the store's states and by re-interpreting its source, the
/// same text either way; bad lines and ids are usage errors.
/// </summary>
public sealed class ProgramStartCliTests : IDisposable
{
    private const string Program =
        "G21 G90 G17\nG10 L2 P2 X30. Y-20. Z5.\nG55\nG00 X0 Y0 Z10.\nG52 X10. Y10.\nG01 X5. F300.\nT2 M06\nG43 H2 Z20.\n" +
        "S9000 M03\nG00 X-5. Y-5.\nG01 X40. F500\nY30.\nG20\nG00 X1. Y1. Z0.5\nG01 Z-0.1 F10.\nG21\nG00 Z30.\nM05\nM30\n";

    private readonly TestFolder _folder = new("programs-start");

    public void Dispose() => _folder.Dispose();

    [Fact]
    public void The_preamble_from_the_store_is_the_one_re_interpretation_prints()
    {
        var (location, id) = Import();
        foreach (var line in new[] { 2, 7, 12, 16 })
        {
            var stored = Run(location, id, line, reinterpret: false);
            var again = Run(location, id, line, reinterpret: true);
            stored.Code.Should().Be(0, stored.Stderr);
            stored.Stdout.Should().StartWith("start at line ").And.Be(again.Stdout, $"line {line}: the store's states give the re-interpreted preamble");
            stored.Stderr.Should().Contain("planned from the store");
            again.Stderr.Should().Contain("planned by re-interpreting the source");
        }

        var preamble = Run(location, id, 12, reinterpret: false).Stdout.Split('\n', StringSplitOptions.RemoveEmptyEntries);
        preamble[0].Should().Be("start at line 12");
        preamble.Should().Contain(l => l.Contains("G55", StringComparison.Ordinal), "the work offset the skipped blocks chose is restored");
    }

    [Fact]
    public void A_line_without_motion_after_it_a_line_below_one_and_an_unknown_program_are_refused()
    {
        var (location, id) = Import();
        Run(location, id, 19, false).Should().Match<(int Code, string Stdout, string Stderr)>(r => r.Code == CliGlobals.UsageOrIo && r.Stdout.Length == 0);
        Run(location, id, 0, false).Stderr.Should().Contain("--from-line must be 1 or more");
        Run(location, 987_654_321, 3, false).Stderr.Should().Contain("no program 987654321");
    }

    private (StoreLocation Location, long Id) Import()
    {
        var location = StoreLocation.Sqlite(Path.Combine(_folder.Path, "store.db"));
        var file = Path.Combine(_folder.Path, "start.nc");
        File.WriteAllText(file, Program, new UTF8Encoding(false));
        using var store = ProgramStores.Open(location);
        return (location, store.ImportRevision(file, MachineProfile.Default).Id);
    }

    private static (int Code, string Stdout, string Stderr) Run(StoreLocation location, long id, int line, bool reinterpret)
    {
        var stdout = new StringWriter();
        var stderr = new StringWriter();
        try
        {
            var code = ProgramStartCommand.Run(location, id, line, reinterpret, false, stdout, stderr, CancellationToken.None);
            return (code, stdout.ToString(), stderr.ToString());
        }
        catch (CliException e)
        {
            return (e.ExitCode, stdout.ToString(), stderr + "pmacstream programs start: " + e.Message);
        }
    }
}
