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

        var modal = LoadModal();
        var file = WriteMdiProgram(modal, blocks);
        var profile = Options.Profile;
        PreparedProgram prepared;
        try
        {
            var settings = Options.Settings with { Shape = Options.Settings.Shape with { ProgramTail = string.Empty } };
            prepared = await _jobs.PrepareAsync(new PrepareRequest(file, settings) { Profile = profile }, null, cancellationToken).ConfigureAwait(false);
        }
        catch (ProgramRefusedException e)
        {
            var lines = e.Diagnostics.Where(d => d.Severity == Severity.Error).Select(d => $"mdi:{d.Line - 1}:{d.Column}: error {d.Code}: {d.Message}");
            return ConsoleResult.Refused(ConsoleRefusal.CheckFailed, $"refused by the check: {string.Join("; ", lines.DefaultIfEmpty(e.Message))}");
        }

        Log.Information("MDI on {Device:l}: {Blocks:l}{Modal:l}", Controller.Description, string.Join(" | ", blocks), modal is null ? string.Empty : $" (modal state {modal})");
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
        SaveModal(ModalLine(file, profile));
        return failed ?? ConsoleResult.Ok($"ran {blocks.Count} MDI block{(blocks.Count == 1 ? string.Empty : "s")} (job {job.Id})");
    }

    /// <summary>The modal state MDI carries to its next call on this controller, as a block (<c>G21 G90 G17 G54 G01 F500</c>), or null.</summary>
    public string? CarriedModalState => LoadModal();

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

    private string WriteMdiProgram(string? modal, IReadOnlyList<string> blocks)
    {
        var folder = Path.Combine(Path.GetDirectoryName(Path.GetFullPath(Options.StatePath ?? _jobs.JobDatabase))!, "mdi");
        Directory.CreateDirectory(folder);
        var file = Path.Combine(folder, string.Create(CultureInfo.InvariantCulture, $"mdi-{DateTime.UtcNow:yyyyMMdd-HHmmss-fff}-{Environment.ProcessId}.nc"));
        var text = new StringBuilder();
        text.Append(modal ?? "(MDI)").Append('\n'); // line 1: the carried modal state, so the operator's blocks are lines 2..
        foreach (var b in blocks)
        {
            text.Append(b.Trim()).Append('\n');
        }

        File.WriteAllText(file, text.ToString(), new UTF8Encoding(false));
        return file;
    }

    /// <summary>The modal state after the MDI program, read by the interpreter, as one block.</summary>
    private static string ModalLine(string file, MachineProfile profile)
    {
        var interpreter = new Interpreter(profile);
        foreach (var block in GCodeReader.ReadAll(file))
        {
            interpreter.Step(block);
        }

        var s = interpreter.State;
        var line = new StringBuilder();
        line.Append(s.Units == LengthUnits.Inches ? "G20" : "G21").Append(s.Absolute ? " G90" : " G91");
        line.Append(CultureInfo.InvariantCulture, $" G{s.Plane} G{s.WorkOffset}");
        if (s.Motion is 0 or 1)
        {
            line.Append(CultureInfo.InvariantCulture, $" G0{s.Motion}");
        }

        if (s.Feed is { } f)
        {
            line.Append(CultureInfo.InvariantCulture, $" F{f:0.####}");
        }

        if (s.LengthCompensation is 43 or 44 && s.LengthOffset > 0)
        {
            line.Append(CultureInfo.InvariantCulture, $" G{s.LengthCompensation} H{s.LengthOffset}");
        }

        return line.ToString();
    }

    private string? LoadModal()
    {
        if (Options.StatePath is not { } path || !File.Exists(path))
        {
            return null;
        }

        try
        {
            using var doc = JsonDocument.Parse(File.ReadAllBytes(path));
            return doc.RootElement.TryGetProperty(Controller.Spec.ToString(), out var e) && e.TryGetProperty("mdiModal", out var m) ? m.GetString() : null;
        }
        catch (JsonException e)
        {
            Log.Warning("Console state {Path:l} not read ({Message:l}): MDI starts from the power-on modal state", path, e.Message);
            return null;
        }
    }

    private void SaveModal(string modal)
    {
        if (Options.StatePath is not { } path)
        {
            return;
        }

        var all = new Dictionary<string, string>(StringComparer.Ordinal);
        if (File.Exists(path))
        {
            try
            {
                using var doc = JsonDocument.Parse(File.ReadAllBytes(path));
                foreach (var p in doc.RootElement.EnumerateObject())
                {
                    if (p.Value.ValueKind == JsonValueKind.Object && p.Value.TryGetProperty("mdiModal", out var m) && m.GetString() is { } text)
                    {
                        all[p.Name] = text;
                    }
                }
            }
            catch (JsonException)
            {
                // A broken state file is replaced: it only carries MDI's modal state.
            }
        }

        all[Controller.Spec.ToString()] = modal;
        using var buffer = new MemoryStream();
        using (var w = new Utf8JsonWriter(buffer, new JsonWriterOptions { Indented = true }))
        {
            w.WriteStartObject();
            foreach (var (spec, text) in all)
            {
                w.WriteStartObject(spec);
                w.WriteString("mdiModal", text);
                w.WriteEndObject();
            }

            w.WriteEndObject();
        }

        Directory.CreateDirectory(Path.GetDirectoryName(Path.GetFullPath(path))!);
        File.WriteAllBytes(path, buffer.ToArray());
        Log.Information("MDI modal state now {Modal:l}", modal);
    }
}
