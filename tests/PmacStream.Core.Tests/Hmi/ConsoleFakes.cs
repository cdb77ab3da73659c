using PmacStream.Hmi;
using PmacStream.Machine;

namespace PmacStream.Core.Tests.Hmi;

/// <summary>A console view that records what the presenter shows and lets tests raise the form's events.</summary>
internal sealed class FakeConsoleView : IConsoleView
{
    public HmiLanguage Language { get; set; }
    public event EventHandler? LanguageChanged;
    public event EventHandler? HomeAllRequested;
    public event EventHandler<string>? HomeAxisRequested;
    public event EventHandler<JogEventArgs>? JogPressed;
    public event EventHandler<JogEventArgs>? JogReleased;
    public event EventHandler? MdiRequested;
    public event EventHandler<int>? MdiHistoryPicked;
    public event EventHandler? ClearAlarmsRequested;
    public event EventHandler<string>? TouchOffRequested;
    public event EventHandler? OffsetsApplyRequested;
    public event EventHandler? ToolsApplyRequested;
    public event EventHandler? TablesReloadRequested;
    public event EventHandler? LoadLibraryRequested;
    public event EventHandler? HistoryRefreshRequested;

    public string JogAxis { get; set; } = "X";
    public double? JogIncrement { get; set; }
    public double JogFeed { get; set; }
    public string MdiText { get; set; } = string.Empty;
    public double TouchValue { get; set; }
    public IReadOnlyList<string> ConsoleAxes { get; set; } = [];
    public IReadOnlyList<DroRow> Dro { get; set; } = [];
    public string MachineSummary { get; set; } = string.Empty;
    public string AlarmBanner { get; set; } = string.Empty;
    public string ConsoleMessage { get; set; } = string.Empty;
    public IReadOnlyList<string> MdiHistory { get; set; } = [];
    public IReadOnlyList<string> AlarmHistory { get; set; } = [];
    public IReadOnlyList<string> JobHistory { get; set; } = [];
    public IReadOnlyList<IReadOnlyList<string>> OffsetRows { get; set; } = [];
    public IReadOnlyList<IReadOnlyList<string>> ToolRows { get; set; } = [];
    public string TablesMessage { get; set; } = string.Empty;
    public bool ConsoleEnabled { get; set; }
    public bool JogEnabled { get; set; }
    public bool ConfirmAnswer { get; set; } = true;
    public List<string> Confirmations { get; } = [];

    public Task<bool> ConfirmAsync(string title, string text)
    {
        Confirmations.Add(text);
        return Task.FromResult(ConfirmAnswer);
    }

    public void ChangeLanguage(HmiLanguage language)
    {
        Language = language;
        LanguageChanged?.Invoke(this, EventArgs.Empty);
    }

    public void HomeAll() => HomeAllRequested?.Invoke(this, EventArgs.Empty);
    public void Home(string axis) => HomeAxisRequested?.Invoke(this, axis);
    public void PressJog(int direction) => JogPressed?.Invoke(this, new JogEventArgs(direction));
    public void ReleaseJog(int direction) => JogReleased?.Invoke(this, new JogEventArgs(direction));
    public void SendMdi(string block)
    {
        MdiText = block;
        MdiRequested?.Invoke(this, EventArgs.Empty);
    }

    public void PickMdi(int index) => MdiHistoryPicked?.Invoke(this, index);
    public void ClearAlarms() => ClearAlarmsRequested?.Invoke(this, EventArgs.Empty);
    public void TouchOff(string axis) => TouchOffRequested?.Invoke(this, axis);
    public void ApplyOffsets() => OffsetsApplyRequested?.Invoke(this, EventArgs.Empty);
    public void ApplyTools() => ToolsApplyRequested?.Invoke(this, EventArgs.Empty);
    public void Reload() => TablesReloadRequested?.Invoke(this, EventArgs.Empty);
    public void LoadLibrary() => LoadLibraryRequested?.Invoke(this, EventArgs.Empty);
    public void RefreshHistory() => HistoryRefreshRequested?.Invoke(this, EventArgs.Empty);

    /// <summary>Sets one cell of the offsets grid, as the operator's typing does.</summary>
    public void EditOffset(string table, int column, string text) =>
        OffsetRows = OffsetRows.Select(r => r[0] == table ? (IReadOnlyList<string>)r.Select((c, i) => i == column ? text : c).ToList() : r).ToList();

    /// <summary>Sets one cell of the tools grid.</summary>
    public void EditTool(int tool, int column, string text) =>
        ToolRows = ToolRows.Select(r => r[0] == tool.ToString(System.Globalization.CultureInfo.InvariantCulture) ? (IReadOnlyList<string>)r.Select((c, i) => i == column ? text : c).ToList() : r).ToList();
}

/// <summary>A console backend whose machine is a few fields: it records the commands and answers as told.</summary>
internal sealed class FakeConsoleBackend : IConsoleBackend
{
    public bool ConsoleReady { get; set; } = true;
    public List<string> Calls { get; } = [];
    public double[] Machine { get; } = new double[9];
    public bool[] Homed { get; } = new bool[9];

    /// <summary>The machine's axes (a profile may list up to nine).</summary>
    public string[] Names { get; set; } = ["X", "Y", "Z"];
    public List<MachineAlarm> Alarms { get; } = [];
    public MachineMode Mode { get; set; } = MachineMode.Idle;
    public ConsoleResult? Refuse { get; set; }
    public MachineTables Tables { get; set; } = MachineTables.Empty;
    public List<AlarmRecord> History { get; } = [];
    public List<HmiJobEntry> Jobs { get; } = [];

    public Task<MachineState> ReadStateAsync(CancellationToken cancellationToken = default)
    {
        Calls.Add("state");
        var axes = Names.Select((n, i) => new AxisState(n, i + 1, Machine[i], Machine[i] - Tables.Offset("G54")[i], 0, Homed[i])).ToList();
        return Task.FromResult(new MachineState(Mode, axes, [.. Alarms], "G54", 100, 500, 0, null, 0, null));
    }

    public Task<ConsoleResult> HomeAsync(string? axes, CancellationToken cancellationToken = default) => Do($"home {axes ?? "all"}", () =>
    {
        foreach (var i in Enumerable.Range(0, Names.Length).Where(i => axes is null || axes.Contains(Names[i], StringComparison.Ordinal)))
        {
            Machine[i] = 0;
            Homed[i] = true;
        }
    });

    public Task<ConsoleResult> JogAsync(string axis, double distance, double? feed, CancellationToken cancellationToken = default) =>
        Do(FormattableString.Invariant($"jog {axis} {distance} F{feed}"), () => Machine[Array.IndexOf(Names, axis)] += distance);

    public Task<ConsoleResult> StartJogAsync(string axis, int direction, double? feed, CancellationToken cancellationToken = default) =>
        Do(FormattableString.Invariant($"start {axis}{direction} F{feed}"), () => { });

    public Task<ConsoleResult> StopJogAsync(string axis, CancellationToken cancellationToken = default) => Do($"stop {axis}", () => { });

    public Task<ConsoleResult> MdiAsync(IReadOnlyList<string> blocks, CancellationToken cancellationToken = default) => Do("mdi " + string.Join("|", blocks), () => { });

    public Task<ConsoleResult> ClearAlarmsAsync(CancellationToken cancellationToken = default) => Do("clear", Alarms.Clear);

    public Task<MachineTables> ReadTablesAsync(CancellationToken cancellationToken = default) => Task.FromResult(Tables);

    public Task<ConsoleResult> SetWorkOffsetAsync(string name, double? x, double? y, double? z, CancellationToken cancellationToken = default) =>
        Do(FormattableString.Invariant($"offset {name} X{x} Y{y} Z{z}"), () =>
        {
            var o = Tables.Offset(name);
            Tables = Tables.With(o with { X = x ?? o.X, Y = y ?? o.Y, Z = z ?? o.Z });
        });

    public Task<ConsoleResult> TouchOffAsync(string name, string axis, double value, CancellationToken cancellationToken = default) =>
        Do(FormattableString.Invariant($"touch {name} {axis} {value}"), () => { });

    public Task<ConsoleResult> SetToolAsync(int number, double length, double radius, double lengthWear, double radiusWear, CancellationToken cancellationToken = default) =>
        Do(FormattableString.Invariant($"tool {number} {length} {radius} {lengthWear} {radiusWear}"), () => Tables = Tables.With(new ToolEntry(number, length, radius, lengthWear, radiusWear)));

    public IReadOnlyList<AlarmRecord> AlarmHistory() => History;

    public IReadOnlyList<HmiJobEntry> JobHistory() => Jobs;

    private Task<ConsoleResult> Do(string call, Action effect)
    {
        Calls.Add(call);
        if (Refuse is { } refused)
        {
            return Task.FromResult(refused);
        }

        effect();
        return Task.FromResult(ConsoleResult.Ok(call));
    }
}
