namespace PmacStream.Core.Tests.Kit;

/// <summary>The parts of the shared test kit that decide what a test sees: tool lookup and the executed-line fold.</summary>
public sealed class TestKitTests : IDisposable
{
    private readonly string _dir = Directory.CreateTempSubdirectory("pmacstream-kit-").FullName;

    public void Dispose() => Directory.Delete(_dir, true);

    [SkippableFact]
    [System.Runtime.Versioning.UnsupportedOSPlatform("windows")]
    public void A_tool_is_found_only_where_the_search_path_says_and_only_when_executable()
    {
        Requires.NotWindows("Unix file modes");
        var bin = Directory.CreateDirectory(Path.Combine(_dir, "bin")).FullName;
        var other = Directory.CreateDirectory(Path.Combine(_dir, "other")).FullName;
        var tool = Path.Combine(bin, "fake-socat");
        File.WriteAllText(tool, "#!/bin/sh\n");
        File.SetUnixFileMode(tool, UnixFileMode.UserRead | UnixFileMode.UserWrite);
        Tools.Find("fake-socat", bin).Should().BeNull("a file without an execute bit is not a tool");

        File.SetUnixFileMode(tool, UnixFileMode.UserRead | UnixFileMode.UserWrite | UnixFileMode.UserExecute);
        Tools.Find("fake-socat", other + Path.PathSeparator + bin).Should().Be(tool);
        Tools.Find("fake-socat", other).Should().BeNull("a folder left off the path hides the tool");
    }

    [Fact]
    public void Executed_lines_fold_repeats_of_one_block_and_leave_out_the_preamble()
    {
        MoveLines.Fold([0, 0, 3, 3, 3, 5, 7, 7, 5]).Should().Equal(3, 5, 7, 5);
        MoveLines.Fold([]).Should().BeEmpty();
    }

    [Fact]
    public void The_repository_root_holds_the_solution_and_the_demo_program()
    {
        File.Exists(Path.Combine(RepoRoot.Path, "PmacStream.sln")).Should().BeTrue();
        File.Exists(RepoRoot.DemoProgram).Should().BeTrue();
        RepoRoot.Sample("plc", "x.ladder").Should().Be(Path.Combine(RepoRoot.Path, "samples", "plc", "x.ladder"));
    }
}
