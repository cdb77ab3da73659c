namespace PmacStream.Core.Tests.Kit;

/// <summary>The parts of the shared test kit that decide what a test sees: tool lookup and the executed-line fold.</summary>
public sealed class TestKitTests : IDisposable
{
    private readonly TestFolder _temp = new("kit");

    public void Dispose() => _temp.Dispose();

    [SkippableFact]
    [System.Runtime.Versioning.UnsupportedOSPlatform("windows")]
    public void A_tool_is_found_only_where_the_search_path_says_and_only_when_executable()
    {
        Requires.NotWindows("Unix file modes");
        var bin = Directory.CreateDirectory(Path.Combine(_temp.Path, "bin")).FullName;
        var other = Directory.CreateDirectory(Path.Combine(_temp.Path, "other")).FullName;
        var tool = Path.Combine(bin, "fake-socat");
        File.WriteAllText(tool, "#!/bin/sh\n");
        File.SetUnixFileMode(tool, UnixFileMode.UserRead | UnixFileMode.UserWrite);
        Tools.Find("fake-socat", bin).Should().BeNull("a file without an execute bit is not a tool");

        File.SetUnixFileMode(tool, UnixFileMode.UserRead | UnixFileMode.UserWrite | UnixFileMode.UserExecute);
        Tools.Find("fake-socat", other + Path.PathSeparator + bin).Should().Be(tool);
        Tools.Find("fake-socat", other).Should().BeNull("a folder left off the path hides the tool");
    }

    [Fact]
    public void Executed_blocks_count_a_block_s_further_moves_once_its_repeats_twice_and_leave_out_the_preamble()
    {
        MoveLines.Blocks([(0, false), (0, false), (3, true), (3, false), (3, false), (5, true), (7, true), (7, false), (5, true)]).Should().Equal(3, 5, 7, 5);
        MoveLines.Blocks([(4, true), (4, true), (0, true), (4, true)]).Should().Equal(new[] { 4, 4, 4 }, "a one-move block run again, also after a preamble move");
        MoveLines.Blocks([(2, false), (2, false), (3, false)]).Should().Equal(new[] { 2, 3 }, "moves without marks: where the line changes");
        MoveLines.Blocks(Array.Empty<(int, bool)>()).Should().BeEmpty();
    }

    [Fact]
    public void The_repository_root_holds_the_solution_and_the_demo_program()
    {
        File.Exists(Path.Combine(RepoRoot.Path, "PmacStream.sln")).Should().BeTrue();
        File.Exists(RepoRoot.DemoProgram).Should().BeTrue();
        RepoRoot.Sample("plc", "x.ladder").Should().Be(Path.Combine(RepoRoot.Path, "samples", "plc", "x.ladder"));
    }
}
