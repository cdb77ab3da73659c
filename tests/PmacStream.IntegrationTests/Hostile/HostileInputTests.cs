using System.Text;
using PmacStream.IntegrationTests.Streaming;

namespace PmacStream.IntegrationTests.Hostile;

/// <summary>
/// Runs docs/hostile-inputs.md: every row's input is made by the generator its name picks, the command runs in the
/// test's process through the CLI's own entry (<see cref="CliRun"/>: the same parser, handlers and exit-code
/// convention, its log captured as the process's console shows it), and the exit code, the message and the absence of
/// a stack trace are checked. A few rows also run as the real process (<see cref="ProcessSample"/>), to prove the
/// binary says and exits the same.
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

    /// <summary>
    /// The rows that also run as a process: a usage-or-I/O error (a folder given as a program, exit 2), a bad file
    /// (UTF-16: <c>FILE:LINE:COL: error CODE:</c>, exit 1) and a damaged job database (an SQLite error that would leave
    /// the process as a stack trace if the CLI did not catch it; moved aside, exit 2).
    /// </summary>
    private static readonly (string Name, string Command)[] ProcessSample =
    [
        ("program-folder", "split {file}"),
        ("program-utf16", "check {file}"),
        ("jobdb-page-damaged", "resume --job-db {db} --yes"),
    ];

    public static IEnumerable<object[]> ProcessRows() =>
        Rows().Where(r => ProcessSample.Contains(((string)r[0], (string)r[1])));

    [Theory]
    [MemberData(nameof(Rows))]
    public async Task Each_hostile_input_gets_its_message_its_exit_code_and_no_stack_trace(string name, string command, int exit, string says)
    {
        var row = Row.Make(name, command);
        using var log = new StringWriter();
        (int Code, string Out, string Err) run;
        using (LogCapture.Begin(log))
        {
            run = await CliRun.InProcessAsync(row.Args);
        }

        row.Check(exit, says, run.Code, run.Out + run.Err + log);
    }

    [Theory]
    [MemberData(nameof(ProcessRows))]
    public async Task The_binary_gives_a_sampled_row_the_same_exit_code_and_output_as_the_run_in_process(string name, string command, int exit, string says)
    {
        var process = Row.Make(name, command);
        var (code, stdout, stderr) = CliProcess.Run(process.Args);
        process.Check(exit, says, code, stdout + stderr);

        var inProcess = Row.Make(name, command);
        using var log = new StringWriter();
        (int Code, string Out, string Err) run;
        using (LogCapture.Begin(log))
        {
            run = await CliRun.InProcessAsync(inProcess.Args);
        }

        run.Code.Should().Be(code);
        process.Normalize(stdout).Should().Equal(inProcess.Normalize(run.Out), "the same standard output");
        // Two writers share standard error (the command's messages, the log's console sink): their lines may interleave
        // either way, so the lines are compared, not their order.
        process.Normalize(stderr).Order().Should().Equal(inProcess.Normalize(run.Err + log).Order(), "the same standard error, the log included");
    }

    [Fact]
    public void ProcessSample_names_rows_of_the_table()
    {
        ProcessRows().Should().HaveCount(ProcessSample.Length, "every sampled row is in docs/hostile-inputs.md");
    }

    [Fact]
    public async Task A_usage_error_is_the_same_one_line_and_exit_code_as_a_process_and_in_process()
    {
        string[] args = ["split"]; // no file: a required argument missing
        var (code, stdout, stderr) = CliProcess.Run(args);
        var run = await CliRun.InProcessAsync(args);

        code.Should().Be(2, stderr);
        stderr.Should().Contain("Required argument missing").And.Contain("Try 'pmacstream --help'.").And.NotContain("   at ");
        (run.Code, run.Out, run.Err).Should().Be((code, stdout, stderr));
    }

    [Fact]
    public void A_logged_exception_in_a_run_in_process_shows_its_stack_trace_as_the_process_would()
    {
        // What the rows' "no stack trace" rests on in process: the log of the run is in its output.
        using var log = new StringWriter();
        using (LogCapture.Begin(log))
        {
            Serilog.Log.ForContext<HostileInputTests>().Error(Thrown(), "a fault");
        }

        log.ToString().Should().Contain("ERR] a fault").And.Contain("InvalidOperationException").And.Contain("   at ");
    }

    private static InvalidOperationException Thrown()
    {
        try
        {
            throw new InvalidOperationException("thrown");
        }
        catch (InvalidOperationException e)
        {
            return e;
        }
    }

    /// <summary>One row's input, made in a folder of its own, and the command line that reads it.</summary>
    private sealed record Row(string Name, string Command, string Folder, string Made, string Png)
    {
        public string[] Args => Command.Split(' ').Select(Fill).ToArray();

        public static Row Make(string name, string command)
        {
            var folder = HostileJobDatabases.Folder(name);
            return new Row(name, command, folder, Generators[name](folder), Path.Combine(folder, "out.png"));
        }

        public string Fill(string text) => text.Replace("{db}", Made).Replace("{file}", Made).Replace("{png}", Png);

        /// <summary>The output's lines with this row's folder, the moved-aside file's time and a log line's time taken out, to compare two runs.</summary>
        public string[] Normalize(string output)
        {
            var text = System.Text.RegularExpressions.Regex.Replace(output.Replace(Folder, "{folder}"), @"\.damaged-[^\s:;,)]+", ".damaged-{time}");
            text = System.Text.RegularExpressions.Regex.Replace(text, @"^\[\d\d:\d\d:\d\d\.\d{3} ", "[{time} ", System.Text.RegularExpressions.RegexOptions.Multiline);
            return text.Split('\n');
        }

        public void Check(int exit, string says, int code, string output)
        {
            code.Should().Be(exit, output);
            output.Should().Contain(Fill(says));
            output.Should().NotContain("   at ").And.NotContain("Exception").And.NotContain("unexpected error");
            if (Name.StartsWith("jobdb-", StringComparison.Ordinal) && says.Contains("moved aside", StringComparison.Ordinal))
            {
                Directory.EnumerateFiles(Folder, "jobs.db.damaged-*").Should().NotBeEmpty("the damaged file is kept");
            }

            if (Command.Contains("{png}", StringComparison.Ordinal) && exit != 0)
            {
                File.Exists(Png).Should().BeFalse("a failed preview writes no picture");
            }
        }
    }

    [SkippableFact]
    public async Task Check_into_a_store_on_a_full_disk_names_the_file_and_the_full_disk()
    {
        Requires.NotWindows("a tmpfs of 16 KiB stands in for a full disk");
        var disk = HostileJobDatabases.Folder("fulldisk");
        var (mounted, why) = Run("mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", disk);
        Skip.If(mounted != 0, $"cannot mount a 16 KiB tmpfs as a full disk (needs root): {why}");
        try
        {
            var program = Write(HostileJobDatabases.Folder("fullsrc"), "part.nc", Encoding.ASCII.GetBytes("G21 G90\nG00 X0 Y0\nG01 X10 F100\nM30\n"));
            var db = Path.Combine(disk, "program.db");

            var (code, stdout, stderr) = await CliRun.InProcessAsync(["check", program, "--db", db]);

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
