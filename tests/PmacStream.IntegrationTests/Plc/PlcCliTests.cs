using PmacStream.Cli;
using PmacStream.Cli.Commands;

namespace PmacStream.IntegrationTests.Plc;

public sealed class PlcCliTests : IDisposable
{
    private readonly TestFolder _temp = new("plc-cli");

    public void Dispose() => _temp.Dispose();

    private static async Task<(int Code, string Out, string Err)> Run(string path, int? plc, string? outPath)
    {
        var stdout = new StringWriter();
        var stderr = new StringWriter();
        var code = await PlcCommand.RunAsync(path, plc, outPath, stdout, stderr, CancellationToken.None);
        return (code, stdout.ToString(), stderr.ToString());
    }

    [Fact]
    public async Task Writes_the_program_to_standard_output()
    {
        var (code, stdout, stderr) = await Run(PlcSamples.Path_("motor-fwd-rev.ladder"), null, null);
        code.Should().Be(CliGlobals.Ok);
        stderr.Should().BeEmpty();
        stdout.Should().Contain("OPEN PLC 10 CLEAR\r\n")
            .And.Contain("M900=(M800^1)&(M801|M900)&(M901^1)&(M803^1)")
            .And.Contain("M901=(M800^1)&(M802|M901)&(M900^1)&(M803^1)")
            .And.EndWith("ENABLE PLC 10\r\n");
    }

    [Fact]
    public async Task Plc_option_overrides_the_file_and_out_writes_the_file()
    {
        var outPath = Path.Combine(_temp.Path, "motor.pmc");
        var (code, stdout, stderr) = await Run(PlcSamples.Path_("motor-fwd-rev.ladder"), 4, outPath);
        code.Should().Be(CliGlobals.Ok);
        stdout.Should().BeEmpty();
        stderr.Should().Contain("PLC 4: 2 rungs");
        var text = await File.ReadAllTextAsync(outPath);
        text.Should().Contain("OPEN PLC 4 CLEAR").And.Contain("ENABLE PLC 4").And.NotContain("PLC 10");
        Directory.GetFiles(_temp.Path).Should().ContainSingle("no temporary file is left behind");
    }

    [Fact]
    public async Task Ladder_errors_print_file_line_column_exit_1_and_write_nothing()
    {
        var bad = Path.Combine(_temp.Path, "bad.ladder");
        await File.WriteAllTextAsync(bad, "input A 0\noutput B 0\nB = A & (C\nB = A\n");
        var outPath = Path.Combine(_temp.Path, "bad.pmc");
        var (code, stdout, stderr) = await Run(bad, null, outPath);
        code.Should().Be(CliGlobals.Failed);
        stdout.Should().BeEmpty();
        stderr.Should().Contain($"{bad}:3:10: error: 'C' is not declared")
            .And.Contain($"{bad}:4:1: error: coil 'B' is already driven by the rung on line 3")
            .And.Contain("2 error(s); no program written.");
        File.Exists(outPath).Should().BeFalse();
    }

    [Fact]
    public async Task Missing_file_and_bad_plc_number_are_usage_errors()
    {
        var missing = async () => await Run(Path.Combine(_temp.Path, "nope.ladder"), null, null);
        (await missing.Should().ThrowAsync<CliException>()).Which.ExitCode.Should().Be(CliGlobals.UsageOrIo);
        var badPlc = async () => await Run(PlcSamples.Path_("motor-fwd-rev.ladder"), 32, null);
        (await badPlc.Should().ThrowAsync<CliException>()).Which.Message.Should().Contain("0..31");
    }

    [Fact]
    public async Task Unwritable_output_is_a_usage_error_and_leaves_nothing()
    {
        var outPath = Path.Combine(_temp.Path, "no-such-dir", "x.pmc");
        var act = async () => await Run(PlcSamples.Path_("motor-fwd-rev.ladder"), null, outPath);
        (await act.Should().ThrowAsync<CliException>()).Which.ExitCode.Should().Be(CliGlobals.UsageOrIo);
        Directory.GetFileSystemEntries(_temp.Path).Should().BeEmpty();
    }

    [Fact]
    public async Task Command_line_errors_exit_2_without_a_stack_trace()
    {
        var (code, _, stderr) = await CliRun.InProcessAsync(["plc", Path.Combine(_temp.Path, "nope.ladder")]);
        code.Should().Be(CliGlobals.UsageOrIo);
        stderr.Should().Contain("nope.ladder: no such file").And.NotContain("   at ");
    }

    [Fact]
    public async Task Command_line_parsing_wires_the_argument_and_options()
    {
        var outPath = Path.Combine(_temp.Path, "spindle.pmc");
        var (code, _, _) = await CliRun.InProcessAsync(["plc", PlcSamples.Path_("sand-mould-spindle.ladder"), "--plc", "12", "--out", outPath]);
        code.Should().Be(CliGlobals.Ok);
        (await File.ReadAllTextAsync(outPath)).Should().Contain("OPEN PLC 12 CLEAR").And.Contain("M902=");
    }
}
