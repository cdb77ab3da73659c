using System.Globalization;
using System.Text;
using System.Text.Json;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Streaming;

namespace PmacStream.Machine;

/// <summary>
/// MDI: blocks typed at the machine run as a little program through the same gate as any program (the check under
/// the machine profile, the host conversion, the library), recorded in the job store. The modal state a call leaves
/// (units, distance mode, plane, work offset, motion mode, feed, tool length) carries on to the next call, as on a
/// control: it is kept on the host, per controller, in <see cref="MachineConsoleOptions.StatePath"/>, and written as
/// the first line of the next MDI program.
/// </summary>
public sealed partial class MachineConsole
{
    /// <summary>Runs MDI blocks and returns once they ran and the axes are in position.</summary>
    public async Task<ConsoleResult> MdiAsync(IReadOnlyList<string> blocks, CancellationToken cancellationToken = default)
    {
        ArgumentNullException.ThrowIfNull(blocks);
        if (blocks.Count == 0 || blocks.Any(b => string.IsNullOrWhiteSpace(b) || b.Contains('\n', StringComparison.Ordinal) || b.Contains('\r', StringComparison.Ordinal)))
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue, "MDI needs one or more blocks, each on one line");
        }

        if (await RefuseProgramAsync(cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        var carried = CarriedModal();
        var header = await HeaderAsync(carried, cancellationToken).ConfigureAwait(false);
        var (file, still) = WriteMdiProgram(carried, header, blocks);
        var profile = Options.Profile;
        if (GCode.Expansion.ProgramExpansion.Applies(file, profile))
        {
            // The expander finds a subprogram in the program's own file or in files beside it; MDI blocks have neither.
            return ConsoleResult.Refused(ConsoleRefusal.BadValue,
                "mdi: subprogram and macro calls, variables and loops (M98, M97, G65, G66, #, IF, WHILE, o-words) are not run in MDI: the expander finds a subprogram in the program's own file or beside it, and MDI blocks have neither; put them in a program file and run it");
        }

        var after = ModalAfter(file, profile, still);
        if (after.Compensation is { } comp)
        {
            return ConsoleResult.Refused(ConsoleRefusal.BadValue,
                $"mdi:{comp.Line - header.Count}: cutter compensation (G{comp.Code}) is not run in MDI: each MDI call ends at rest, so the compensated path has no next move to turn its corner on; run it in a program");
        }

        PreparedProgram prepared;
        try
        {
            var settings = Options.Settings with { Shape = Options.Settings.Shape with { ProgramTail = string.Empty } };
            prepared = await _jobs.PrepareAsync(new PrepareRequest(file, settings) { Profile = profile }, null, cancellationToken).ConfigureAwait(false);
        }
        catch (ProgramRefusedException e)
        {
            var lines = e.Diagnostics.Where(d => d.Severity == Severity.Error).Select(d => d.Line > header.Count
                ? $"mdi:{d.Line - header.Count}:{d.Column}: error {d.Code}: {d.Message}"
                : $"mdi: the carried modal state ({file}:{d.Line}): error {d.Code}: {d.Message}");
            return ConsoleResult.Refused(ConsoleRefusal.CheckFailed, $"refused by the check: {string.Join("; ", lines.DefaultIfEmpty(e.Message))}");
        }

        Log.Information("MDI on {Device:l}: {Blocks:l} (modal state {Modal:l}{Motion:l}{Cycle:l}, from {Source:l})", Controller.Description, string.Join(" | ", blocks),
            carried.Line, carried.Motion is { } m ? " " + m : string.Empty, carried.Cycle is { } c ? " " + c : string.Empty, carried.Source);
        await using var job = await _jobs.CreateJobAsync(Controller, new JobRequest(prepared.Program, StrategyKind.Chunk)
        {
            Settings = Options.Settings, Profile = prepared.Profile, Library = LibraryPolicy.Verify,
        }, cancellationToken).ConfigureAwait(false);
        await job.StartAsync(cancellationToken).ConfigureAwait(false);
        var outcome = await job.RunAsync(null, cancellationToken).ConfigureAwait(false);
        if (outcome != JobOutcome.Completed)
        {
            return ConsoleResult.Refused(ConsoleRefusal.Failed, $"MDI job {job.Id} {outcome.ToString().ToLowerInvariant()}: {job.Status.Message}");
        }

        var failed = await WaitAsync(Options.Axes, _ => true, cancellationToken).ConfigureAwait(false);
        SaveModal(after.Carried, job.Id);
        return failed ?? ConsoleResult.Ok($"ran {blocks.Count} MDI block{(blocks.Count == 1 ? string.Empty : "s")} (job {job.Id})");
    }

    /// <summary>
    /// The modal state the next MDI call on this controller starts from, as a block (<c>G21 G90 G17 G55 G01 F500</c>,
    /// then <c>G02</c> or <c>G03</c> when an arc mode is in force), or null at power-on.
    /// </summary>
    public string? CarriedModalState => CarriedModal() is { Source: not "power-on" } c
        ? c.Line + (c.Motion is { } m ? " " + m : string.Empty) + (c.Cycle is { } cy ? " " + cy : string.Empty)
        : null;

    /// <summary>Why a program (MDI, a job) cannot start now, or null: one runs, an alarm stops motion, an axis is not homed.</summary>
    private async Task<ConsoleResult?> RefuseProgramAsync(CancellationToken cancellationToken)
    {
        if (await RefuseMotionAsync(null, 0, cancellationToken).ConfigureAwait(false) is { } refused)
        {
            return refused;
        }

        var (unhomed, alarms) = await ReadinessAsync(Connection, Options.Axes, cancellationToken).ConfigureAwait(false);
        if (alarms.Count > 0)
        {
            return ConsoleResult.Refused(ConsoleRefusal.AlarmActive, $"an alarm is active: {alarms[0].Text}");
        }

        return Options.HomeCheck && !Options.Profile.AbsoluteEncoders && unhomed.Count > 0
            ? ConsoleResult.Refused(ConsoleRefusal.NotHomed, $"not homed: {string.Concat(unhomed)} (pmacstream home)")
            : null;
    }

    /// <summary>
    /// Writes the MDI program: the <paramref name="header"/> (the carried modal state, where the axes stand), then the
    /// operator's blocks. Returns it and what is still carried because no block used or replaced it: an arc mode, a
    /// canned cycle.
    /// </summary>
    private (string File, Carry Still) WriteMdiProgram(CarriedMdiState carried, IReadOnlyList<string> header, IReadOnlyList<string> blocks)
    {
        var folder = Path.Combine(Path.GetDirectoryName(Path.GetFullPath(Options.StatePath ?? _jobs.JobDatabase))!, "mdi");
        Directory.CreateDirectory(folder);
        var file = Path.Combine(folder, string.Create(CultureInfo.InvariantCulture, $"mdi-{DateTime.UtcNow:yyyyMMdd-HHmmss-fff}-{Environment.ProcessId}.nc"));
        var text = new StringBuilder();
        foreach (var line in header)
        {
            text.Append(line).Append('\n'); // the operator's blocks follow: error lines are counted from there
        }

        var motion = carried.Motion;
        var cycle = carried.Cycle;
        foreach (var b in blocks)
        {
            var block = b.Trim();
            switch (CarriesMotion(block))
            {
                case true when cycle is not null:
                    // A canned cycle in force drills at a block that only positions (FANUC): the block gets the cycle
                    // code and the R/Z/Q/P it does not write itself, at the end so the columns stay the operator's.
                    text.Append(block).Append(' ').Append(MissingCycleWords(block, cycle)).Append('\n');
                    cycle = null;
                    continue;
                case true when motion is not null:
                    // An arc mode cannot be written on a line of its own (G02 needs an end point): the first move the
                    // operator writes without a motion code gets it, at the end so the columns stay the operator's.
                    text.Append(block).Append(' ').Append(motion).Append('\n');
                    motion = null;
                    continue;
                case null:
                    motion = null; // the block names its own motion or cycle code, which is in force from here on
                    cycle = null;
                    break;
            }

            text.Append(block).Append('\n');
        }

        File.WriteAllText(file, text.ToString(), new UTF8Encoding(false));
        return (file, new Carry(motion, cycle));
    }

    /// <summary>The carried cycle's code and the words of it (R, Z, Q, P) that <paramref name="block"/> does not write.</summary>
    private static string MissingCycleWords(string block, string cycle)
    {
        var written = GCodeReader.LexLine(block).WordList.Select(w => char.ToUpperInvariant(w.Letter)).ToHashSet();
        return string.Join(' ', cycle.Split(' ', StringSplitOptions.RemoveEmptyEntries).Where(w => w[0] == 'G' || !written.Contains(w[0])));
    }

    /// <summary>True when the block moves in the motion mode in force (axis words, only modal G codes), null when it names a motion code, else false.</summary>
    private static bool? CarriesMotion(string block)
    {
        var axes = false;
        foreach (var w in GCodeReader.LexLine(block).WordList)
        {
            if (w.Letter == 'G')
            {
                switch (CodeRoles.OfG(w.CodeTimesTen))
                {
                    case GRole.Motion or GRole.Cycle or GRole.CycleCancel:
                        return null;
                    case not GRole.Mode:
                        return false; // G04, G10, G28, G53, G92 ... take the axis words themselves
                }
            }

            axes |= char.ToUpperInvariant(w.Letter) is 'X' or 'Y' or 'Z' or 'A' or 'B' or 'C' or 'U' or 'V' or 'W';
        }

        return axes;
    }

    /// <summary>The modal state after the MDI program, read by the interpreter, and the first block that turns cutter compensation on.</summary>
    private static (CarriedMdiState Carried, (int Line, string Code)? Compensation) ModalAfter(string file, MachineProfile profile, Carry still)
    {
        var interpreter = new Interpreter(profile);
        var cycle = new CycleWords();
        (int Line, string Code)? compensation = null;
        foreach (var block in GCodeReader.ReadAll(file))
        {
            interpreter.Execute(block); // the modal state is all it reads: no record of the block
            cycle.After(block, interpreter.State);
            if (compensation is null && interpreter.State.RadiusCompensation is { } rc && Math.Floor(rc) is 41 or 42)
            {
                compensation = (block.LineNumber, rc.ToString("0.#", CultureInfo.InvariantCulture));
            }
        }

        var (line, motion) = ModalLine(interpreter, profile, ended: false, still.Motion);
        return (new CarriedMdiState(line, motion, "MDI") { Cycle = still.Cycle ?? cycle.Text }, compensation);
    }

    /// <summary>
    /// The modal state a job left on this controller: its program read up to the last block that ran (all of it when it
    /// completed), with the library's program end applied (M02/M30: G54, G90, no tool length), or null when the program
    /// cannot be read again (gone, or expanded from subprograms and macros, whose M0 counts expanded blocks).
    /// </summary>
    private CarriedMdiState? ModalAfterJob(JobRecord job)
    {
        var through = job.Checkpoint is { State: SessionState.Completed } ? int.MaxValue : job.Checkpoint?.LastExecutedLine ?? 0;
        if (through <= 0 || job.SourceLocation is not null || !File.Exists(job.ProgramPath))
        {
            Log.Information("MDI's modal state not taken from job {Id}: {Why:l}", job.Id,
                through <= 0 ? "no block of it ran" : job.SourceLocation is not null ? "its program was expanded" : $"{job.ProgramPath} is gone");
            return null;
        }

        var interpreter = new Interpreter(Options.Profile);
        var cycle = new CycleWords();
        var ended = false;
        foreach (var block in GCodeReader.ReadAll(job.ProgramPath))
        {
            if (block.LineNumber > through)
            {
                break;
            }

            interpreter.Execute(block); // the modal state is all it reads: no record of the block
            cycle.After(block, interpreter.State);
            ended |= block.WordList.Exists(static w => w.Letter == 'M' && CodeRoles.EndsProgram(w.CodeTimesTen));
        }

        var (line, motion) = ModalLine(interpreter, Options.Profile, ended, null);
        return new CarriedMdiState(line, motion, string.Create(CultureInfo.InvariantCulture, $"job {job.Id}")) { Cycle = ended ? null : cycle.Text };
    }

    /// <summary>The modal state as one block, and an arc mode in force (<c>G02</c>, <c>G03</c>) apart: it needs an end point.</summary>
    private static (string Line, string? Motion) ModalLine(Interpreter interpreter, MachineProfile profile, bool ended, string? arcStillCarried)
    {
        var s = interpreter.State;
        var line = new StringBuilder();
        line.Append(s.Units == LengthUnits.Inches ? "G20" : "G21").Append(s.Absolute || ended ? " G90" : " G91");
        line.Append(CultureInfo.InvariantCulture, $" G{s.Plane} ");
        var selected = interpreter.Coordinates.Selected;
        line.Append(ended ? "G54" : selected switch
        {
            >= 5410 => string.Create(CultureInfo.InvariantCulture, $"G54.1 P{selected - 5410}"),
            591 or 592 or 593 => string.Create(CultureInfo.InvariantCulture, $"G59.{selected - 590}"),
            _ => string.Create(CultureInfo.InvariantCulture, $"G{s.WorkOffset}"),
        });
        if (s.Motion is 0 or 1 && arcStillCarried is null)
        {
            line.Append(CultureInfo.InvariantCulture, $" G0{s.Motion}");
        }

        if (s.Feed is { } f)
        {
            line.Append(CultureInfo.InvariantCulture, $" F{f:0.####}");
        }

        if (!ended && s.LengthCompensation is 43 or 44 && s.LengthOffset > 0)
        {
            line.Append(CultureInfo.InvariantCulture, $" G{s.LengthCompensation} H{s.LengthOffset}");
        }

        if (profile.GGroupOf(98) is >= 0 and var group && s.GetG(group) is 98 or 99)
        {
            line.Append(CultureInfo.InvariantCulture, $" G{s.GetG(group)}"); // the canned cycles' return level
        }

        return (line.ToString(), arcStillCarried ?? (s.Motion is 2 or 3 ? $"G0{s.Motion}" : null));
    }

    /// <summary>
    /// Where the next MDI starts: after the newest job on this controller when it is newer than the last MDI (a
    /// program ran in between), else the last MDI's state (<see cref="MachineConsoleOptions.StatePath"/>), else power-on.
    /// </summary>
    private CarriedMdiState CarriedModal()
    {
        var saved = LoadModal();
        if (LatestJob() is { } latest && (saved is null || (saved.JobId is { } j && latest.Id > j)) && ModalAfterJob(latest) is { } fromJob)
        {
            return fromJob;
        }

        return saved is null ? new CarriedMdiState("(MDI)", null, "power-on") : saved.Carried;
    }

    private SavedMdiState? LoadModal()
    {
        if (Options.StatePath is not { } path || !File.Exists(path))
        {
            return null;
        }

        try
        {
            using var doc = JsonDocument.Parse(File.ReadAllBytes(path));
            if (!doc.RootElement.TryGetProperty(Controller.Spec.ToString(), out var e) || !e.TryGetProperty("mdiModal", out var m) || m.GetString() is not { } line)
            {
                return null;
            }

            var motion = e.TryGetProperty("mdiMotion", out var mm) ? mm.GetString() : null;
            var cycle = e.TryGetProperty("mdiCycle", out var mc) ? mc.GetString() : null;
            long? job = e.TryGetProperty("mdiJob", out var id) && id.TryGetInt64(out var n) ? n : null;
            return new SavedMdiState(new CarriedMdiState(line, motion, job is null ? "MDI" : $"MDI job {job}") { Cycle = cycle }, job);
        }
        catch (JsonException e)
        {
            Log.Warning("Console state {Path:l} not read ({Message:l}): MDI starts from the power-on modal state", path, e.Message);
            return null;
        }
    }

    private void SaveModal(CarriedMdiState modal, long? jobId)
    {
        if (Options.StatePath is not { } path)
        {
            return;
        }

        var all = new Dictionary<string, JsonElement>(StringComparer.Ordinal);
        if (File.Exists(path))
        {
            try
            {
                using var doc = JsonDocument.Parse(File.ReadAllBytes(path));
                foreach (var p in doc.RootElement.EnumerateObject())
                {
                    if (p.Value.ValueKind == JsonValueKind.Object)
                    {
                        all[p.Name] = p.Value.Clone();
                    }
                }
            }
            catch (JsonException)
            {
                // A broken state file is replaced: it only carries MDI's modal state.
            }
        }

        var key = Controller.Spec.ToString();
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer, new JsonWriterOptions { Indented = true }))
        {
            w.WriteStartObject();
            foreach (var (spec, value) in all.Where(p => p.Key != key))
            {
                w.WritePropertyName(spec);
                value.WriteTo(w);
            }

            w.WriteStartObject(key);
            w.WriteString("mdiModal", modal.Line);
            if (modal.Motion is { } motion)
            {
                w.WriteString("mdiMotion", motion);
            }

            if (modal.Cycle is { } cycle)
            {
                w.WriteString("mdiCycle", cycle);
            }

            if (jobId is { } id)
            {
                w.WriteNumber("mdiJob", id); // a job on this controller newer than this one left its own modal state
            }
            w.WriteEndObject();
            w.WriteEndObject();
        }

        Directory.CreateDirectory(Path.GetDirectoryName(Path.GetFullPath(path))!);
        File.WriteAllBytes(path, buffer.ToArray());
        Log.Information("MDI modal state now {Modal:l}{Motion:l}{Cycle:l}", modal.Line, modal.Motion is { } m ? " " + m : string.Empty, modal.Cycle is { } c ? " " + c : string.Empty);
    }

    /// <summary>The modal state an MDI call starts from: the block of line 1, an arc mode and a canned cycle apart, and where it came from.</summary>
    private sealed record CarriedMdiState(string Line, string? Motion, string Source)
    {
        /// <summary>The canned cycle in force with the words it keeps (<c>G81 R2 Z-5</c>), or null.</summary>
        public string? Cycle { get; init; }
    }

    /// <summary>What an MDI call still carries after its blocks because none used or replaced it.</summary>
    private sealed record Carry(string? Motion, string? Cycle);

    private sealed record SavedMdiState(CarriedMdiState Carried, long? JobId);
}
