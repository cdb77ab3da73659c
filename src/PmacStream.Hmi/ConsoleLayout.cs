namespace PmacStream.Hmi;

/// <summary>
/// Where the console pages sit: a tab control (Machine, Offsets, Tools, History) to the right of the paper's screen
/// (<see cref="HmiLayout"/>, which keeps its place and size), under the alarm banner, which shows whatever tab is
/// chosen. Boxes of the tab pages' children are relative to the page. The form places its controls here and the UI
/// test clicks here.
/// </summary>
public static class ConsoleLayout
{
    /// <summary>Width of the console column right of the paper's screen.</summary>
    public const int Width = 600;

    /// <summary>The form's client width: the paper's screen and the console column.</summary>
    public const int FormWidth = HmiLayout.ClientWidth + Width;

    /// <summary>The alarm banner (hidden while no alarm is active).</summary>
    public static readonly LayoutBox AlarmBanner = new(HmiLayout.ClientWidth + 4, 8, Width - 12, 44);

    /// <summary>The tab control of the console pages.</summary>
    public static readonly LayoutBox Tabs = new(HmiLayout.ClientWidth + 4, 56, Width - 12, HmiLayout.ClientHeight - 64);

    /// <summary>Height of the tab headers (a page's client starts below them).</summary>
    public const int TabHeaderHeight = 24;

    /// <summary>Left of a page's client inside the tab control.</summary>
    public const int PageInset = 4;

    // ---- Machine page

    /// <summary>DRO column lefts and widths: axis, machine, work, to go, homed, home button, touch-off button.</summary>
    public static readonly IReadOnlyList<(int X, int Width)> DroColumns = [(6, 30), (38, 110), (150, 110), (262, 96), (360, 50), (412, 70), (484, 92)];

    /// <summary>Top of the DRO's header row; axis rows follow <see cref="DroRowHeight"/> apart.</summary>
    public const int DroTop = 8;

    /// <summary>Height of a DRO row.</summary>
    public const int DroRowHeight = 32;

    /// <summary>A DRO cell of a three-axis machine: <paramref name="row"/> 0 is the header, 1.. the axes.</summary>
    public static LayoutBox DroCell(int row, int column) => DroCell(row, column, 3);

    /// <summary>
    /// A DRO cell of a machine with <paramref name="axes"/> axes: the header and one row per axis share the height of
    /// a three-axis DRO (rows <see cref="DroRowHeight"/> apart up to three axes, closer beyond), so the controls below
    /// stay where they are whatever the machine.
    /// </summary>
    public static LayoutBox DroCell(int row, int column, int axes)
    {
        var height = DroRowPitch(axes);
        return new(DroColumns[column].X, DroTop + (row * height), DroColumns[column].Width, height - 4);
    }

    /// <summary>The rows' pitch for <paramref name="axes"/> axes: 32 px up to three, the three-axis DRO's height shared beyond (13 px at nine).</summary>
    public static int DroRowPitch(int axes) => axes <= 3 ? DroRowHeight : (4 * DroRowHeight) / (axes + 1);

    /// <summary>The DRO's font size (points) for <paramref name="axes"/> axes: 14 up to three, smaller as the rows close up.</summary>
    public static float DroFontSize(int axes) => axes <= 3 ? 14f : Math.Max(6f, 14f * (DroRowPitch(axes) - 4) / (DroRowHeight - 4));

    /// <summary>Touch-off value label.</summary>
    public static readonly LayoutBox TouchValueLabel = new(6, 142, 150, 20);
    /// <summary>Touch-off value box.</summary>
    public static readonly LayoutBox TouchValueBox = new(160, 138, 90, 23);
    /// <summary>Home all button.</summary>
    public static readonly LayoutBox HomeAllButton = new(262, 136, 110, 28);
    /// <summary>Load library button.</summary>
    public static readonly LayoutBox LoadLibraryButton = new(380, 136, 130, 28);
    /// <summary>Mode, offset, feeds, spindle, override.</summary>
    public static readonly LayoutBox SummaryLabel = new(6, 170, 570, 40);

    /// <summary>Jog group box.</summary>
    public static readonly LayoutBox JogGroup = new(6, 214, 570, 110);
    /// <summary>Jog axis label.</summary>
    public static readonly LayoutBox JogAxisLabel = new(10, 24, 40, 20);
    /// <summary>Jog axis combo.</summary>
    public static readonly LayoutBox JogAxisCombo = new(52, 20, 60, 23);
    /// <summary>Jog step label.</summary>
    public static readonly LayoutBox JogStepLabel = new(122, 24, 50, 20);
    /// <summary>Jog step combo (0.001, 0.01, 0.1, 1 mm, continuous).</summary>
    public static readonly LayoutBox JogStepCombo = new(174, 20, 110, 23);
    /// <summary>Jog speed label.</summary>
    public static readonly LayoutBox JogSpeedLabel = new(294, 24, 110, 20);
    /// <summary>Jog speed box, mm/min.</summary>
    public static readonly LayoutBox JogSpeedBox = new(406, 20, 80, 23);
    /// <summary>Jog minus button.</summary>
    public static readonly LayoutBox JogMinusButton = new(52, 56, 100, 40);
    /// <summary>Jog plus button.</summary>
    public static readonly LayoutBox JogPlusButton = new(174, 56, 100, 40);

    /// <summary>MDI group box.</summary>
    public static readonly LayoutBox MdiGroup = new(6, 330, 570, 220);
    /// <summary>MDI line.</summary>
    public static readonly LayoutBox MdiText = new(10, 22, 440, 23);
    /// <summary>MDI send button.</summary>
    public static readonly LayoutBox MdiSendButton = new(458, 20, 100, 27);
    /// <summary>MDI history list.</summary>
    public static readonly LayoutBox MdiHistoryList = new(10, 54, 548, 156);

    /// <summary>Clear alarms button.</summary>
    public static readonly LayoutBox ClearAlarmsButton = new(6, 558, 130, 30);
    /// <summary>What the last command did.</summary>
    public static readonly LayoutBox ConsoleMessageLabel = new(144, 558, 432, 60);

    // ---- Offsets and Tools pages

    /// <summary>A table page's grid.</summary>
    public static readonly LayoutBox TableGrid = new(6, 6, 570, 720);
    /// <summary>A table page's Apply button.</summary>
    public static readonly LayoutBox ApplyButton = new(6, 734, 130, 30);
    /// <summary>A table page's Reload button.</summary>
    public static readonly LayoutBox ReloadButton = new(144, 734, 110, 30);
    /// <summary>A table page's message (validation errors, what was written).</summary>
    public static readonly LayoutBox TableMessageLabel = new(6, 770, 570, 90);

    // ---- History page

    /// <summary>Jobs label.</summary>
    public static readonly LayoutBox JobHistoryLabel = new(6, 8, 300, 20);
    /// <summary>Jobs list.</summary>
    public static readonly LayoutBox JobHistoryList = new(6, 30, 570, 380);
    /// <summary>Alarm history label.</summary>
    public static readonly LayoutBox AlarmHistoryLabel = new(6, 420, 300, 20);
    /// <summary>Alarm history list.</summary>
    public static readonly LayoutBox AlarmHistoryList = new(6, 442, 570, 380);
    /// <summary>Refresh button.</summary>
    public static readonly LayoutBox RefreshButton = new(6, 830, 110, 28);

    /// <summary>Store page: where the store is.</summary>
    public static readonly LayoutBox StoreLocationLabel = new(6, 8, 570, 20);

    /// <summary>Store page: the store's job history.</summary>
    public static readonly LayoutBox StoreJobsGrid = new(6, 30, 570, 220);

    /// <summary>Store page: the shop label.</summary>
    public static readonly LayoutBox StoreShopLabel = new(6, 256, 300, 20);

    /// <summary>Store page: the shop (machines, who runs what, the current line).</summary>
    public static readonly LayoutBox StoreShopGrid = new(6, 278, 570, 132);

    /// <summary>Store page: the programs label.</summary>
    public static readonly LayoutBox StoreProgramsLabel = new(6, 418, 300, 20);

    /// <summary>Store page: the store's program revisions.</summary>
    public static readonly LayoutBox StoreProgramsGrid = new(6, 440, 570, 360);

    /// <summary>Store page: read the lists again.</summary>
    public static readonly LayoutBox StoreRefreshButton = new(6, 808, 110, 28);

    /// <summary>Store page: open the selected revision.</summary>
    public static readonly LayoutBox StoreOpenButton = new(124, 808, 150, 28);

    /// <summary>Store page: what the last action did.</summary>
    public static readonly LayoutBox StoreMessageLabel = new(282, 808, 294, 52);
}
