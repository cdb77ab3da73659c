using System.CommandLine;
using System.Diagnostics;
using System.Globalization;
using PmacStream.GCode;
using PmacStream.Preparation;
using PmacStream.Preparation.Store;

namespace PmacStream.Cli.Commands;

/// <summary>
/// <c>pmacstream programs start ID --from-line N [--reinterpret] [--safe-z-highest]</c>: the preamble of a start at
/// the block of a line of a stored revision, as <c>stream --program ID --from-line N</c> shows it before it runs: read
/// from the store's stored states, or with <c>--reinterpret</c> by interpreting the revision's source from the top (the
/// way every start went before the store; the benchmark times both). The time it took goes to stderr.
/// </summary>
internal static class ProgramStartCommand
{
    public static Command Create(Option<string?> store)
    {
        var id = new Argument<long>("id") { Description = "Program revision id." };
        var line = new Option<int>("--from-line") { Description = "Start at the block of this source line.", Required = true };
        var reinterpret = new Option<bool>("--reinterpret") { Description = "Interpret the revision's source from the top instead of reading the stored states." };
        var to = new Option<int?>("--to-line") { Description = "Selected blocks: the range ends after the block of this line (a move); checked against the stored blocks." };
        var call = new Option<int?>("--call") { Description = "In a program with subprograms, macros or loops: the Nth time the --from-line source line runs (read from the revision's stored source map)." };
        var file = new Option<string?>("--file") { Description = "In a program with subprograms in other files: the file or called program (O1002) the --from-line line is a line of." };
        var highest = new Option<bool>("--safe-z-highest") { Description = "Retract above the highest Z reached so far (else the fixed safe Z)." };
        var cmd = new Command("start", "Show the preamble of a start at a line of a stored revision (what stream --program ID --from-line N sends first).");
        cmd.Arguments.Add(id);
        cmd.Options.Add(line);
        cmd.Options.Add(to);
        cmd.Options.Add(call);
        cmd.Options.Add(file);
        cmd.Options.Add(reinterpret);
        cmd.Options.Add(highest);
        cmd.SetAction((parse, ct) => new ProgramStartHandler().RunAsync(
            new ProgramStartOptions(StoreOptions.Resolve(parse.GetValue(store)), parse.GetValue(id), parse.GetValue(line), parse.GetValue(reinterpret), parse.GetValue(highest), parse.GetValue(to), parse.GetValue(call), parse.GetValue(file)), CliConsole.Of(parse), ct));
        return cmd;
    }

    /// <summary>Prints the start's block line and preamble; returns the exit code.</summary>
    public static int Run(StoreLocation location, long programId, int line, bool reinterpret, bool highestSoFar, TextWriter output, TextWriter error, CancellationToken ct, int? toLine = null,
        (int? Call, string? File) run = default)
    {
        if (line < 1)
        {
            throw new CliException("--from-line must be 1 or more");
        }

        var clock = Stopwatch.StartNew();
        using var store = ProgramsCommand.OpenStore(location);
        var info = store.GetProgram(programId) ?? throw new CliException($"no program {programId} in {location.Display}");
        var profile = MachineProfile.BuiltInNames.Contains(info.Profile, StringComparer.OrdinalIgnoreCase) ? MachineProfile.Resolve(info.Profile) : MachineProfile.Default;
        var where = ExpandedLine(store, programId, ref line, run);
        if (where is not null && toLine is not null)
        {
            throw new CliException("--to-line runs lines of one program in order; this program calls subprograms, macros or loops, whose lines run more than once: a range is refused", CliGlobals.Failed);
        }

        var options = new StartPlanOptions { Profile = profile, SafeZMode = highestSoFar ? SafeZMode.HighestSoFar : SafeZMode.Fixed };
        StartPlan plan;
        try
        {
            plan = reinterpret
                ? StartFromLine.Plan(StoredPrograms.Materialize(store, info), line, options, ct)
                : StartFromLine.Plan(store, programId, line, options);
        }
        catch (ArgumentOutOfRangeException e)
        {
            throw new CliException(e.Message.Split(Environment.NewLine)[0]);
        }
        catch (StoredStateMissingException e)
        {
            throw new CliException($"{e.Message}: give --reinterpret, or import it again");
        }

        // Checked before anything is printed: a refused range prints nothing but why.
        var rangeEnd = toLine is { } last ? RangeEnd(store, programId, line, last) : null;
        if (where is not null)
        {
            output.WriteLine(where);
        }

        output.WriteLine(string.Create(CultureInfo.InvariantCulture, $"start at line {plan.Line}"));
        foreach (var g in plan.GCode)
        {
            output.WriteLine(g);
        }

        if (rangeEnd is not null)
        {
            output.WriteLine(rangeEnd);
        }

        error.WriteLine(string.Create(CultureInfo.InvariantCulture, $"planned {(reinterpret ? "by re-interpreting the source" : "from the store")} in {clock.Elapsed.TotalMilliseconds:0.0} ms"));
        return CliGlobals.Ok;
    }

    /// <summary>
    /// A revision whose program was expanded numbers its blocks by expanded line: a source line (of a subprogram file,
    /// with its run) is found through the stored source map (<see cref="PmacStream.Jobs.SourceLocations.Resolve"/>), and said where it is
    /// (<c>starting at O1002 line 7, call 3 of 4 from line 12 (expanded line 95)</c>). Null for a program not expanded.
    /// </summary>
    private static string? ExpandedLine(IProgramRevisions store, long programId, ref int line, (int? Call, string? File) run)
    {
        if (store.ReadExpansionMap(programId) is not { } map)
        {
            return run.Call is null && run.File is null ? null
                : throw new CliException($"--call and --file choose a run of a line in a program with subprograms, macros or loops; program {programId} has no stored source map (none, or imported before this version stored it: import it again)");
        }

        try
        {
            var expanded = PmacStream.Jobs.SourceLocations.Resolve(map, line, run.Call, run.File);
            line = expanded;
            return string.Create(CultureInfo.InvariantCulture, $"starting at {map.Describe(expanded)} (expanded line {expanded})");
        }
        catch (PmacStream.Jobs.JobException e)
        {
            throw new CliException(e.Message);
        }
    }

    /// <summary>
    /// Selected blocks (<c>--to-line</c>): the range checked against the stored blocks (refused with why, exit 1) and its
    /// end: the blocks it runs and where the machine stands after its last one (machine coordinates, the interpreter's end of that block).
    /// </summary>
    private static string RangeEnd(IProgramRevisions store, long programId, int from, int to)
    {
        try
        {
            var range = StoredRange.Check(store, programId, from, to);
            var end = range.Last.End;
            return string.Create(CultureInfo.InvariantCulture, $"end after line {range.ToLine}: {range.Blocks} blocks, at X{end.X:0.###} Y{end.Y:0.###} Z{end.Z:0.###}");
        }
        catch (ArgumentException e)
        {
            throw new CliException($"lines {from}..{to}: {e.Message}", CliGlobals.Failed);
        }
    }
}

/// <summary>What a <c>programs start</c> command line asks for.</summary>
/// <param name="Store">The store.</param>
/// <param name="Id">The revision.</param>
/// <param name="FromLine">The source line whose block the start is at.</param>
/// <param name="Reinterpret">Interpret the source from the top instead of reading the stored states.</param>
/// <param name="SafeZHighest">Retract above the highest Z reached so far (else the fixed safe Z).</param>
/// <param name="ToLine">Selected blocks: the range ends after the block of this line; null: to the program's end.</param>
/// <param name="Call">In an expanded program: the Nth time the source line runs.</param>
/// <param name="File">In an expanded program: the file or called program the line is a line of.</param>
internal sealed record ProgramStartOptions(StoreLocation Store, long Id, int FromLine, bool Reinterpret, bool SafeZHighest, int? ToLine = null, int? Call = null, string? File = null);

/// <summary><c>pmacstream programs start</c>: prints the preamble of a start at a line of a stored revision (<see cref="ProgramStartCommand.Run"/>).</summary>
internal sealed class ProgramStartHandler
{
    /// <summary>Prints the start's block line and preamble; returns the exit code.</summary>
    public Task<int> RunAsync(ProgramStartOptions o, CliConsole console, CancellationToken ct) =>
        Task.FromResult(ProgramStartCommand.Run(o.Store, o.Id, o.FromLine, o.Reinterpret, o.SafeZHighest, console.Out, console.Error, ct, o.ToLine, (o.Call, o.File)));
}
