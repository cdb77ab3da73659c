using System.Globalization;
using PmacStream.GCode;
using PmacStream.Jobs;
using Serilog;

namespace PmacStream.Hmi;

/// <summary>
/// The machine profile selector, the check and the job gate's split under the chosen profile, and the diagnostics
/// list they fill: what the screen knows of the open program's fitness to run. Runs on the UI thread.
/// </summary>
internal sealed class ProgramGatePanel(IMainView view, IHmiBackend backend, ILogger log)
{
    /// <summary>The machine profile programs are checked, split, drawn and run under.</summary>
    public MachineProfile Profile { get; private set; } = MachineProfile.Default;

    /// <summary>The last check's or refusal's findings, null when none is shown.</summary>
    public HmiCheckResult? Check { get; private set; }

    /// <summary>Shows the selector with the built-in profiles (and <paramref name="initial"/>'s name when it is a file's) and selects <paramref name="initial"/>.</summary>
    public void ShowProfiles(MachineProfile initial)
    {
        Profile = initial;
        view.Profiles = MachineProfile.BuiltInNames.Contains(initial.Name, StringComparer.OrdinalIgnoreCase)
            ? MachineProfile.BuiltInNames
            : [.. MachineProfile.BuiltInNames, initial.Source];
        view.SelectedProfile = MachineProfile.BuiltInNames.Contains(initial.Name, StringComparer.OrdinalIgnoreCase) ? initial.Name : initial.Source;
    }

    /// <summary>
    /// Takes the profile the operator selected; true when it is another one (the check is dropped: it was made under
    /// the old profile). Refused while a job runs (the selector goes back): a job runs under one profile.
    /// </summary>
    public bool ChooseProfile(bool jobActive)
    {
        var name = view.SelectedProfile;
        if (jobActive)
        {
            view.SelectedProfile = MachineProfile.BuiltInNames.Contains(Profile.Name, StringComparer.OrdinalIgnoreCase) ? Profile.Name : Profile.Source;
            throw new InvalidOperationException("A job is running: the machine profile can change between jobs.");
        }

        var chosen = MachineProfile.Resolve(name);
        if (chosen.Identity == Profile.Identity)
        {
            return false;
        }

        log.Information("Machine profile {Old:l} -> {New:l}: the check and the split are made again under it", Profile.Name, chosen.Name);
        Profile = chosen;
        Clear();
        return true;
    }

    /// <summary>Checks a program under the profile and lists every finding.</summary>
    public async Task CheckAsync(string path, HmiLanguage language, CancellationToken cancellationToken)
    {
        var result = await backend.CheckAsync(path, Profile, language, cancellationToken).ConfigureAwait(true);
        Show(result);
        log.Information("Checked {Path:l} under {Profile:l}: " + HmiText.Get(TextId.CheckSummary, HmiLanguage.English), path, Profile.Name, result.Errors, result.Warnings, result.Blocks);
    }

    /// <summary>
    /// The gate and the split: refused programs show every finding in the list and fail with the first one (or the
    /// codes the controller cannot run yet) as an <see cref="InvalidOperationException"/> for the operator.
    /// </summary>
    public async Task<SplitView> SplitAsync(string path, RunSettings settings, HmiLanguage language, CancellationToken cancellationToken, long? programId = null)
    {
        try
        {
            return await backend.PrepareAsync(path, settings, Profile, programId, cancellationToken).ConfigureAwait(true);
        }
        catch (ProgramRefusedException e)
        {
            Show(HmiCheckResult.FromList(e.Diagnostics, 0));
            if (e.NotRunnableCodes.Count > 0)
            {
                throw new InvalidOperationException(HmiText.Format(TextId.ProgramNotRunnable, language, ProgramGate.Describe(e.NotRunnableCodes), Profile.Name), e);
            }

            var first = e.Diagnostics.FirstOrDefault(d => d.Severity == Severity.Error);
            throw new InvalidOperationException(first is null ? e.Message : HmiText.Format(TextId.ProgramHasErrors, language, first.Format(Path.GetFileName(path))), e);
        }
    }

    /// <summary>The source line of finding <paramref name="index"/>, or null.</summary>
    public int? LineOf(int index) => Check is { } c && index >= 0 && index < c.Diagnostics.Count ? c.Diagnostics[index].Line : null;

    /// <summary>Forgets the findings and empties the list.</summary>
    public void Clear()
    {
        Check = null;
        view.Diagnostics = [];
    }

    private void Show(HmiCheckResult result)
    {
        Check = result;
        view.Diagnostics = result.Diagnostics
            .Select(d => string.Create(CultureInfo.InvariantCulture, $"{d.Line}:{d.Column}  {(d.Severity == Severity.Error ? "E" : "W")}  {d.Code}  {d.Message}"))
            .ToList();
    }
}
