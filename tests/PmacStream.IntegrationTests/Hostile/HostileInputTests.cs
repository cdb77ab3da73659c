using System.Text;
using PmacStream.IntegrationTests.Streaming;

namespace PmacStream.IntegrationTests.Hostile;

/// <summary>
/// Runs docs/hostile-inputs.md: every row's input is made by the generator its name picks, the command runs as a
/// real process, and the exit code, the message and the absence of a stack trace are checked.
/// </summary>
public sealed class HostileInputTests
{
    private static readonly Dictionary<string, Func<string, string>> Generators = new()
    {
        ["jobdb-cp_state-garbage"] = d => HostileJobDatabases.WithField(d, "cp_state", "'garbage'"),
        ["jobdb-cp_state-flags"] = d => HostileJobDatabases.WithField(d, "cp_state", "'Running, Held'"),
        ["jobdb-cp_time-garbage"] = d => HostileJobDatabases.WithField(d, "cp_time", "'yesterday'"),
        ["jobdb-strategy-garbage"] = d => HostileJobDatabases.WithField(d, "strategy", "'warp'"),
        ["jobdb-created-garbage"] = d => HostileJobDatabases.WithField(d, "created", "'soon'"),
        ["jobdb-cp_last_line-null"] = d => HostileJobDatabases.WithField(d, "cp_last_line", "NULL"),
        ["jobdb-cp_last_line-huge"] = d => HostileJobDatabases.WithField(d, "cp_last_line", "9223372036854775807"),
        ["jobdb-cp_chunk-negative"] = d => HostileJobDatabases.WithField(d, "cp_chunk", "-3"),
        ["jobdb-line_probe-command"] = d => HostileJobDatabases.WithField(d, "line_probe", "'P501; #1J+'"),
        ["jobdb-not-a-database"] = HostileJobDatabases.NotADatabase,
        ["jobdb-page-damaged"] = HostileJobDatabases.PageDamaged,
        ["jobdb-wal-missing"] = HostileJobDatabases.WalMissing,
        ["jobdb-wal-damaged"] = HostileJobDatabases.WalDamaged,
        ["jobdb-folder"] = d => Directory.CreateDirectory(Path.Combine(d, "jobs.db")).FullName,
        ["program-folder"] = d => Directory.CreateDirectory(Path.Combine(d, "part.nc")).FullName,
        ["program-empty"] = d => Write(d, "empty.nc", []),
        ["program-utf16"] = d => Write(d, "utf16.nc", Encoding.Unicode.GetPreamble().Concat(Encoding.Unicode.GetBytes("G21 G90\nG00 X0 Y0\nG01 X10 F100\nM30\n")).ToArray()),
        ["program-rejected-words"] = d => Write(d, "rejected.nc", Encoding.ASCII.GetBytes("G21 G90\nG00 X0 Y0\nG999999999999999 X1\nG01 X10 Q7 F100\nU9 X3\nM30\n")),
        ["program-one-line-1mb"] = d => Write(d, "line1mb.nc", Repeat("X ", 1 << 19, "\n")),
        ["program-one-line-9mb"] = d => Write(d, "line9mb.nc", Repeat("X ", 9 << 19, "\n")),
        ["program-all-errors"] = d => Write(d, "allerrors.nc", Repeat(new StringBuilder().Insert(0, "X ", 125).Append('\n').ToString(), 2000, string.Empty)),
        ["program-words-repeated"] = d => Write(d, "words.nc", Repeat("X1", 100_000, "\n")),
    };

    /// <summary><paramref name="text"/> <paramref name="times"/> times, then <paramref name="end"/>, as ASCII.</summary>
    private static byte[] Repeat(string text, int times, string end) =>
        Encoding.ASCII.GetBytes(new StringBuilder(text.Length * times + end.Length).Insert(0, text, times).Append(end).ToString());

    public static IEnumerable<object[]> Rows()
    {
        var doc = File.ReadAllLines(Path.Combine(RepoRoot.Path, "docs", "hostile-inputs.md"));
        foreach (var line in doc.Where(l => l.StartsWith("| `", StringComparison.Ordinal)))
        {
            var cells = line.Split('|', StringSplitOptions.TrimEntries)[1..^1].Select(c => c.Trim('`')).ToArray();
            if (cells.Length == 4 && int.TryParse(cells[2], out var exit))
            {
                yield return [cells[0], cells[1], exit, cells[3]];
            }
        }
    }

    [Fact]
    public void The_list_has_every_kind_of_input_and_a_generator_for_each()
    {
        var rows = Rows().ToList();
        rows.Should().HaveCountGreaterThan(20);
        rows.Select(r => (string)r[0]).Should().OnlyContain(n => Generators.ContainsKey(n), "every named input is made by the test");
    }

    [Theory]
    [MemberData(nameof(Rows))]
    public void Each_hostile_input_gets_its_message_its_exit_code_and_no_stack_trace(string name, string command, int exit, string says)
    {
        var folder = HostileJobDatabases.Folder(name);
        var made = Generators[name](folder);
        var png = Path.Combine(folder, "out.png");
        string Fill(string text) => text.Replace("{db}", made).Replace("{file}", made).Replace("{png}", png);
        var args = command.Split(' ').Select(Fill).ToArray();

        var (code, stdout, stderr) = CliProcess.Run(args);

        var output = stdout + stderr;
        code.Should().Be(exit, output);
        output.Should().Contain(Fill(says));
        output.Should().NotContain("   at ").And.NotContain("Exception").And.NotContain("unexpected error");
        if (name.StartsWith("jobdb-", StringComparison.Ordinal) && says.Contains("moved aside", StringComparison.Ordinal))
        {
            Directory.EnumerateFiles(folder, "jobs.db.damaged-*").Should().NotBeEmpty("the damaged file is kept");
        }

        if (command.Contains("{png}", StringComparison.Ordinal) && exit != 0)
        {
            File.Exists(png).Should().BeFalse("a failed preview writes no picture");
        }
    }

    [SkippableFact]
    public void Check_into_a_store_on_a_full_disk_names_the_file_and_the_full_disk()
    {
        Requires.NotWindows("a tmpfs of 16 KiB stands in for a full disk");
        var disk = HostileJobDatabases.Folder("fulldisk");
        var (mounted, why) = Run("mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", disk);
        Skip.If(mounted != 0, $"cannot mount a 16 KiB tmpfs as a full disk (needs root): {why}");
        try
        {
            var program = Write(HostileJobDatabases.Folder("fullsrc"), "part.nc", Encoding.ASCII.GetBytes("G21 G90\nG00 X0 Y0\nG01 X10 F100\nM30\n"));
            var db = Path.Combine(disk, "program.db");

            var (code, stdout, stderr) = CliProcess.Run("check", program, "--db", db);

            code.Should().Be(2, stdout + stderr);
            stderr.Should().Contain($"--db {db}: ").And.Contain("database or disk is full").And.NotContain("no such table");
            Directory.EnumerateFileSystemEntries(disk).Should().BeEmpty("nothing half-written is left");
        }
        finally
        {
            Run("umount", disk);
        }
    }

    private static (int Code, string Err) Run(string tool, params string[] args)
    {
        var psi = new System.Diagnostics.ProcessStartInfo(tool) { RedirectStandardError = true, RedirectStandardOutput = true };
        args.ToList().ForEach(psi.ArgumentList.Add);
        using var p = System.Diagnostics.Process.Start(psi)!;
        var err = p.StandardError.ReadToEnd();
        p.WaitForExit();
        return (p.ExitCode, err.Trim());
    }

    private static string Write(string folder, string name, byte[] bytes)
    {
        var path = Path.Combine(folder, name);
        File.WriteAllBytes(path, bytes);
        return path;
    }
}
