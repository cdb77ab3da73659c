using System.Globalization;

namespace PmacStream.Hmi;

/// <summary>The languages the HMI can show.</summary>
public enum HmiLanguage
{
    /// <summary>English.</summary>
    English,

    /// <summary>Simplified Chinese.</summary>
    Chinese,
}

/// <summary>Every text the screen shows, by meaning; <see cref="HmiText"/> gives it in a language.</summary>
public enum TextId
{
    /// <summary>Store tab.</summary>
    TabStore,
    /// <summary>Store page: where the store is, {0}.</summary>
    StoreLocation,
    /// <summary>Store page: programs label.</summary>
    StorePrograms,
    /// <summary>Store page: Refresh button.</summary>
    StoreRefresh,
    /// <summary>Store page: Open program button.</summary>
    StoreOpen,
    /// <summary>Store page column: job.</summary>
    StoreColJob,
    /// <summary>Store page column: program.</summary>
    StoreColProgram,
    /// <summary>Store page column: station.</summary>
    StoreColStation,
    /// <summary>Store page column: machine.</summary>
    StoreColMachine,
    /// <summary>Store page column: started.</summary>
    StoreColStarted,
    /// <summary>Store page column: ended.</summary>
    StoreColEnded,
    /// <summary>Store page column: outcome.</summary>
    StoreColOutcome,
    /// <summary>Store page column: blocks.</summary>
    StoreColBlocks,
    /// <summary>Store page column: revision id.</summary>
    StoreColId,
    /// <summary>Store page column: name.</summary>
    StoreColName,
    /// <summary>Store page column: profile.</summary>
    StoreColProfile,
    /// <summary>Store page column: errors.</summary>
    StoreColErrors,
    /// <summary>Store page: {0} jobs, {1} programs in {2}.</summary>
    StoreSummary,
    /// <summary>Store page: Open without a selection.</summary>
    StoreSelectFirst,
    /// <summary>Store page: program {0} ({1}) has {2} errors.</summary>
    StoreHasErrors,
    /// <summary>Store page: opened program {0} ({1}).</summary>
    StoreOpened,
    /// <summary>Store page: opened program {0} ({1}) under profile {2}.</summary>
    StoreOpenedUnder,
    /// <summary>Store page outcome: running.</summary>
    StoreOutcomeRunning,
    /// <summary>Store page outcome: completed.</summary>
    StoreOutcomeCompleted,
    /// <summary>Store page outcome: aborted.</summary>
    StoreOutcomeAborted,
    /// <summary>Store page outcome: interrupted.</summary>
    StoreOutcomeInterrupted,
    /// <summary>Store page outcome: alarm.</summary>
    StoreOutcomeAlarm,
    /// <summary>Window title.</summary>
    Title,
    /// <summary>Connection group box.</summary>
    ConnectionGroup,
    /// <summary>Device type label.</summary>
    DeviceType,
    /// <summary>Device: built-in simulator.</summary>
    DeviceSimulator,
    /// <summary>Device: Ethernet.</summary>
    DeviceEthernet,
    /// <summary>Device: serial port.</summary>
    DeviceSerial,
    /// <summary>Device: PComm32 driver.</summary>
    DevicePcomm,
    /// <summary>IP address label.</summary>
    IpAddress,
    /// <summary>Serial port label.</summary>
    SerialPort,
    /// <summary>Baud label.</summary>
    Baud,
    /// <summary>PComm32 device number label.</summary>
    DeviceNumber,
    /// <summary>Connect button.</summary>
    Connect,
    /// <summary>Disconnect button.</summary>
    Disconnect,
    /// <summary>State: not connected.</summary>
    StateDisconnected,
    /// <summary>State: connecting.</summary>
    StateConnecting,
    /// <summary>State: connected to {0}.</summary>
    StateConnected,
    /// <summary>Program group box.</summary>
    ProgramGroup,
    /// <summary>Open button.</summary>
    Open,
    /// <summary>Check button.</summary>
    Check,
    /// <summary>Split button.</summary>
    Split,
    /// <summary>Blocks per chunk label.</summary>
    BlocksPerChunk,
    /// <summary>Strategy label.</summary>
    Strategy,
    /// <summary>Diagnostics list header.</summary>
    Diagnostics,
    /// <summary>ListBox1 header: chunk files.</summary>
    ChunkFiles,
    /// <summary>Chunk lines header: lines of the selected chunk file.</summary>
    ChunkLines,
    /// <summary>ListBox2 header: program lines.</summary>
    ProgramLines,
    /// <summary>Execute button (程序段执行).</summary>
    Execute,
    /// <summary>Hold button.</summary>
    Hold,
    /// <summary>Resume button.</summary>
    Resume,
    /// <summary>Abort button.</summary>
    Abort,
    /// <summary>Start from selected line button.</summary>
    StartFromLine,
    /// <summary>Resume after interruption button.</summary>
    ResumeInterrupted,
    /// <summary>Single block check box.</summary>
    SingleBlock,
    /// <summary>Optional stop check box (M01 stops).</summary>
    OptionalStop,
    /// <summary>Machine profile selector label.</summary>
    Profile,
    /// <summary>State at a program stop: {0} code, {1} line.</summary>
    StateStopped,
    /// <summary>The program-stop banner: {0} code, {1} line.</summary>
    ProgramStopBanner,
    /// <summary>The gate refused codes the controller cannot run yet: {0} codes and lines, {1} profile.</summary>
    ProgramNotRunnable,
    /// <summary>Status: feed (programmed x override = resulting).</summary>
    Feed,
    /// <summary>Feed override group and status row.</summary>
    FeedOverride,
    /// <summary>What the feed override control does.</summary>
    FeedOverrideHint,
    /// <summary>Download window status row.</summary>
    DownloadWindow,
    /// <summary>Download window control label (percent of a chunk file).</summary>
    WindowControl,
    /// <summary>Download window: {0}-{1} % of a file.</summary>
    WindowPercent,
    /// <summary>Download window while the chunk strategy runs: {0}-{1} %, file {4} at lines {2}-{3}.</summary>
    WindowLines,
    /// <summary>Download window under another strategy: {0}-{1} %, not used by {2}.</summary>
    WindowNotUsed,
    /// <summary>Toolpath pane header (no program).</summary>
    Toolpath,
    /// <summary>Toolpath pane header while drawing: {0} program, {1} percent.</summary>
    ToolpathDrawing,
    /// <summary>Toolpath pane header: {0} program, {1} moves.</summary>
    ToolpathReady,
    /// <summary>Toolpath pane header: {0} program cannot be drawn, {1} why.</summary>
    ToolpathFailed,
    /// <summary>Language selector label.</summary>
    Language,
    /// <summary>Status: total files.</summary>
    TotalFiles,
    /// <summary>Status: program lines.</summary>
    TotalLines,
    /// <summary>Status: current file.</summary>
    CurrentFile,
    /// <summary>Status: current line.</summary>
    CurrentLine,
    /// <summary>Status: progress.</summary>
    Progress,
    /// <summary>Status: elapsed.</summary>
    Elapsed,
    /// <summary>Status: time remaining.</summary>
    Eta,
    /// <summary>Status: job state.</summary>
    JobState,
    /// <summary>Log pane header.</summary>
    Log,
    /// <summary>Confirmation title for start from a line.</summary>
    ConfirmStartTitle,
    /// <summary>Confirmation text: start at line {0} after this preamble: {1}.</summary>
    ConfirmStartText,
    /// <summary>Confirmation text's end of a selected-block start: the job ends after line {0}.</summary>
    ConfirmRangeEnd,
    /// <summary>Confirmation title for resume after interruption.</summary>
    ConfirmResumeTitle,
    /// <summary>Confirmation text: resume job {0} at line {1} (chunk {2}) after this preamble: {3}.</summary>
    ConfirmResumeText,
    /// <summary>Indexing progress: {0} lines indexed.</summary>
    Indexing,
    /// <summary>Check summary: {0} errors, {1} warnings, {2} blocks.</summary>
    CheckSummary,
    /// <summary>Split summary: {0} chunks, {1} blocks.</summary>
    SplitSummary,
    /// <summary>A chunk row: {0} file, {1} first line, {2} last line, {3} blocks.</summary>
    ChunkRow,
    /// <summary>Job states.</summary>
    StateIdle,
    /// <summary>Running.</summary>
    StateRunning,
    /// <summary>Held.</summary>
    StateHeld,
    /// <summary>Completed.</summary>
    StateCompleted,
    /// <summary>Aborted.</summary>
    StateAborted,
    /// <summary>Failed.</summary>
    StateFailed,
    /// <summary>No interrupted job for this program.</summary>
    NoInterruptedJob,
    /// <summary>Start declined by the operator.</summary>
    Declined,
    /// <summary>Select a line first.</summary>
    SelectLineFirst,
    /// <summary>The program has errors: {0}.</summary>
    ProgramHasErrors,
    /// <summary>Closing while a job runs.</summary>
    ConfirmCloseRunning,
    /// <summary>Line number column header.</summary>
    LineColumn,
    /// <summary>Text column header.</summary>
    TextColumn,
    /// <summary>The paper's screen's tab (console pages beside it).</summary>
    TabProgram,
    /// <summary>Console page: DRO, jog, home, MDI, alarms.</summary>
    TabMachine,
    /// <summary>Console page: work offsets.</summary>
    TabOffsets,
    /// <summary>Console page: tool table.</summary>
    TabTools,
    /// <summary>Console page: job and alarm history.</summary>
    TabHistory,
    /// <summary>DRO column: axis.</summary>
    DroAxis,
    /// <summary>DRO column: machine position.</summary>
    DroMachine,
    /// <summary>DRO column: work position.</summary>
    DroWork,
    /// <summary>DRO column: distance to go.</summary>
    DroToGo,
    /// <summary>DRO column: homed.</summary>
    DroHomed,
    /// <summary>Home all button.</summary>
    HomeAll,
    /// <summary>Home one axis button: {0} axis.</summary>
    HomeAxis,
    /// <summary>Jog panel.</summary>
    JogGroup,
    /// <summary>Jog increment label.</summary>
    JogStep,
    /// <summary>Jog increment: continuous.</summary>
    JogContinuous,
    /// <summary>Jog speed label.</summary>
    JogSpeed,
    /// <summary>MDI panel.</summary>
    MdiGroup,
    /// <summary>MDI send button.</summary>
    MdiSend,
    /// <summary>Clear alarms button.</summary>
    ClearAlarms,
    /// <summary>Touch-off button: {0} axis.</summary>
    TouchOffAxis,
    /// <summary>Touch-off value label.</summary>
    TouchValue,
    /// <summary>Load library button.</summary>
    LoadLibrary,
    /// <summary>Write the edited table button.</summary>
    TablesApply,
    /// <summary>Read the tables again button.</summary>
    TablesReload,
    /// <summary>Refresh the histories button.</summary>
    HistoryRefresh,
    /// <summary>Job history label.</summary>
    JobHistoryLabel,
    /// <summary>Alarm history label.</summary>
    AlarmHistoryLabel,
    /// <summary>Machine mode: stopped at a program stop.</summary>
    ModeStopped,
    /// <summary>Machine mode: alarm.</summary>
    ModeAlarm,
    /// <summary>Mode {0}, work offset {1}, feed {2} mm/min (programmed {3}), override {4} %, spindle {5}, job {6}.</summary>
    MachineSummary,
    /// <summary>The spindle on the summary line: actual rpm, then programmed.</summary>
    SpindleReadout,
    /// <summary>Alarm banner: {0} the alarms.</summary>
    AlarmBanner,
    /// <summary>A console command done: {0}.</summary>
    ConsoleDone,
    /// <summary>A console command refused: {0}.</summary>
    ConsoleRefused,
    /// <summary>No controller open.</summary>
    ConnectFirst,
    /// <summary>A cell not a number: {0} row, {1} column, {2} text.</summary>
    TableNumber,
    /// <summary>A cell out of range: {0} row, {1} column, {2} value, {3} min, {4} max.</summary>
    TableRange,
    /// <summary>Validation failed: {0} the errors.</summary>
    TableNotWritten,
    /// <summary>Nothing differs from the controller.</summary>
    TableNoChanges,
    /// <summary>{0} entries written.</summary>
    TableWritten,
    /// <summary>Confirm writing tables.</summary>
    ConfirmTablesTitle,
    /// <summary>{0} the differences.</summary>
    ConfirmTablesText,
    /// <summary>Offsets column: table name.</summary>
    ColTable,
    /// <summary>Tools column: tool number.</summary>
    ColTool,
    /// <summary>Tools column: length.</summary>
    ColLength,
    /// <summary>Tools column: radius.</summary>
    ColRadius,
    /// <summary>Tools column: length wear.</summary>
    ColLengthWear,
    /// <summary>Tools column: radius wear.</summary>
    ColRadiusWear,
    /// <summary>Job history row: {0} id, {1} program, {2} strategy, {3} state, {4} line, {5} time.</summary>
    JobRow,
    /// <summary>Alarm history row: {0} raised, {1} text, {2} cleared or empty.</summary>
    AlarmRow,
    /// <summary>Alarm history: cleared at {0}.</summary>
    AlarmCleared,
    /// <summary>Library loaded under profile {0}.</summary>
    LibraryLoaded,
}

/// <summary>The HMI's string table: English and Simplified Chinese for every <see cref="TextId"/>.</summary>
public static class HmiText
{
    private static readonly Dictionary<TextId, (string En, string Zh)> Table = new()
    {
        [TextId.Title] = ("PmacStream – continuous G-code download", "PmacStream – G代码连续下载"),
        [TextId.ConnectionGroup] = ("Connection", "连接"),
        [TextId.DeviceType] = ("Device", "设备"),
        [TextId.DeviceSimulator] = ("Simulator", "仿真器"),
        [TextId.DeviceEthernet] = ("Ethernet", "以太网"),
        [TextId.DeviceSerial] = ("Serial (RS-232)", "串口 (RS-232)"),
        [TextId.DevicePcomm] = ("PComm32", "PComm32"),
        [TextId.IpAddress] = ("IP address", "IP 地址"),
        [TextId.SerialPort] = ("Port", "端口"),
        [TextId.Baud] = ("Baud", "波特率"),
        [TextId.DeviceNumber] = ("Device no.", "设备号"),
        [TextId.Connect] = ("Connect", "连接"),
        [TextId.Disconnect] = ("Disconnect", "断开"),
        [TextId.StateDisconnected] = ("Not connected", "未连接"),
        [TextId.StateConnecting] = ("Connecting…", "正在连接…"),
        [TextId.StateConnected] = ("Connected: {0}", "已连接：{0}"),
        [TextId.ProgramGroup] = ("Program", "程序"),
        [TextId.Open] = ("Open…", "打开…"),
        [TextId.Check] = ("Check", "检查"),
        [TextId.Split] = ("Split", "拆分"),
        [TextId.BlocksPerChunk] = ("Blocks per chunk", "每块程序段数"),
        [TextId.Strategy] = ("Strategy", "下载策略"),
        [TextId.Diagnostics] = ("Diagnostics", "诊断信息"),
        [TextId.ChunkFiles] = ("Chunk files (ListBox1)", "拆分文件 (ListBox1)"),
        [TextId.ChunkLines] = ("Lines of the selected file", "所选文件的指令行"),
        [TextId.ProgramLines] = ("Program lines (ListBox2)", "程序行 (ListBox2)"),
        [TextId.Execute] = ("Execute", "程序段执行"),
        [TextId.Hold] = ("Hold", "暂停"),
        [TextId.Resume] = ("Resume", "继续"),
        [TextId.Abort] = ("Abort", "终止"),
        [TextId.StartFromLine] = ("Start from selected line", "从所选行开始"),
        [TextId.ResumeInterrupted] = ("Resume after interruption", "断点续加工"),
        [TextId.SingleBlock] = ("Single block", "单段"),
        [TextId.OptionalStop] = ("Optional stop (M01)", "选择停 (M01)"),
        [TextId.Profile] = ("Profile", "机床配置"),
        [TextId.StateStopped] = ("Program stop ({0}) at line {1}", "程序停止 ({0})，第 {1} 行"),
        [TextId.ProgramStopBanner] = ("Program stop ({0}) at line {1}: Resume continues", "程序停止 ({0})，第 {1} 行：按“继续”继续执行"),
        [TextId.ProgramNotRunnable] = ("The controller cannot run {0} yet under profile {1}: the PMAC would skip each code and run the rest of its block",
            "在机床配置 {1} 下控制器尚不能执行 {0}：PMAC 会跳过这些代码而执行程序段的其余部分"),
        [TextId.Feed] = ("Feed", "进给速度"),
        [TextId.FeedOverride] = ("Feed override", "进给倍率"),
        [TextId.FeedOverrideHint] = ("% of the programmed feed (&1 %); the program's F values stay as written",
            "编程进给速度的百分比（&1 %），程序中的 F 值保持不变"),
        [TextId.DownloadWindow] = ("Download window", "下载窗口"),
        [TextId.WindowControl] = ("Window %", "下载窗口 %"),
        [TextId.WindowPercent] = ("{0:0.#}–{1:0.#} % of a file", "文件的 {0:0.#}–{1:0.#} %"),
        [TextId.WindowLines] = ("{0:0.#}–{1:0.#} %: file {4} at lines {2:N0}–{3:N0}", "{0:0.#}–{1:0.#} %：第 {2:N0}–{3:N0} 行下载文件 {4}"),
        [TextId.WindowNotUsed] = ("{0:0.#}–{1:0.#} % (not used by {2})", "{0:0.#}–{1:0.#} %（{2} 策略不使用）"),
        [TextId.Toolpath] = ("Toolpath", "刀具路径"),
        [TextId.ToolpathDrawing] = ("Toolpath of {0}: drawing… {1} %", "{0} 的刀具路径：正在绘制… {1} %"),
        [TextId.ToolpathReady] = ("Toolpath of {0}: {1:N0} moves; executed in green, the tool at the red mark",
            "{0} 的刀具路径：{1:N0} 个移动；绿色为已执行部分，红色标记为刀具位置"),
        [TextId.ToolpathFailed] = ("Toolpath of {0} cannot be drawn: {1}", "{0} 的刀具路径无法绘制：{1}"),
        [TextId.Language] = ("Language", "语言"),
        [TextId.TotalFiles] = ("Files", "文件总数"),
        [TextId.TotalLines] = ("Program lines", "程序行数"),
        [TextId.CurrentFile] = ("Current file", "当前文件"),
        [TextId.CurrentLine] = ("Current line", "当前行"),
        [TextId.Progress] = ("Progress", "执行进度"),
        [TextId.Elapsed] = ("Elapsed", "已用时间"),
        [TextId.Eta] = ("Remaining", "剩余时间"),
        [TextId.JobState] = ("State", "状态"),
        [TextId.Log] = ("Log", "日志"),
        [TextId.ConfirmStartTitle] = ("Start from line", "从指定行开始"),
        [TextId.ConfirmStartText] = ("Start at line {0}. The controller first runs this preamble to restore the machine state:\n\n{1}\n\nStart?",
            "从第 {0} 行开始。控制器先执行以下恢复程序以恢复机床状态：\n\n{1}\n\n是否开始？"),
        [TextId.ConfirmRangeEnd] = ("Selected blocks: the job ends after line {0}; nothing after it is sent.", "选段执行：执行到第 {0} 行为止，之后的程序段不发送。"),
        [TextId.ConfirmResumeTitle] = ("Resume after interruption", "断点续加工"),
        [TextId.ConfirmResumeText] = ("Resume job {0} at line {1} (file {2}). The controller first runs this preamble:\n\n{3}\n\nResume?",
            "继续作业 {0}，从第 {1} 行（文件 {2}）开始。控制器先执行以下恢复程序：\n\n{3}\n\n是否继续？"),
        [TextId.Indexing] = ("Indexing: {0:N0} lines", "正在建立索引：{0:N0} 行"),
        [TextId.CheckSummary] = ("{0} errors, {1} warnings, {2} blocks", "{0} 个错误，{1} 个警告，{2} 个程序段"),
        [TextId.SplitSummary] = ("{0} files, {1} blocks", "{0} 个文件，{1} 个程序段"),
        [TextId.ChunkRow] = ("{0}   lines {1}–{2}   ({3} blocks)", "{0}   第 {1}–{2} 行   （{3} 段）"),
        [TextId.StateIdle] = ("Idle", "空闲"),
        [TextId.StateRunning] = ("Running", "运行中"),
        [TextId.StateHeld] = ("Held", "已暂停"),
        [TextId.StateCompleted] = ("Completed", "已完成"),
        [TextId.StateAborted] = ("Aborted", "已终止"),
        [TextId.StateFailed] = ("Failed", "失败"),
        [TextId.NoInterruptedJob] = ("No interrupted job recorded for this program.", "没有该程序的中断记录。"),
        [TextId.Declined] = ("Not started: the operator declined.", "未开始：操作员取消。"),
        [TextId.SelectLineFirst] = ("Select a program line first.", "请先选择程序行。"),
        [TextId.ConfirmCloseRunning] = ("A job is running. If you close now the controller finishes the lines already downloaded and the job can be resumed later from its checkpoint. Close?",
            "作业正在运行。现在关闭，控制器将执行完已下载的程序行，之后可从断点继续加工。是否关闭？"),
        [TextId.LineColumn] = ("Line", "行号"),
        [TextId.TextColumn] = ("Block", "程序段"),
        [TextId.ProgramHasErrors] = ("The program has errors and cannot be split: {0}", "程序有错误，无法拆分：{0}"),
        [TextId.TabProgram] = ("Program", "程序"),
        [TextId.TabMachine] = ("Machine", "机床"),
        [TextId.TabOffsets] = ("Offsets", "工件坐标系"),
        [TextId.TabTools] = ("Tools", "刀具表"),
        [TextId.TabHistory] = ("History", "历史记录"),
        [TextId.DroAxis] = ("Axis", "轴"),
        [TextId.DroMachine] = ("Machine", "机床坐标"),
        [TextId.DroWork] = ("Work", "工件坐标"),
        [TextId.DroToGo] = ("To go", "剩余距离"),
        [TextId.DroHomed] = ("Homed", "已回零"),
        [TextId.HomeAll] = ("Home all", "全部回零"),
        [TextId.HomeAxis] = ("Home {0}", "{0} 轴回零"),
        [TextId.JogGroup] = ("Jog", "点动"),
        [TextId.JogStep] = ("Step", "步距"),
        [TextId.JogContinuous] = ("Continuous", "连续"),
        [TextId.JogSpeed] = ("Speed mm/min", "速度 mm/min"),
        [TextId.MdiGroup] = ("MDI", "MDI 手动输入"),
        [TextId.MdiSend] = ("Send", "执行"),
        [TextId.ClearAlarms] = ("Clear alarms", "清除报警"),
        [TextId.TouchOffAxis] = ("Touch off {0}", "{0} 轴对零"),
        [TextId.TouchValue] = ("Touch-off value", "对零值"),
        [TextId.LoadLibrary] = ("Load library", "下载程序库"),
        [TextId.TablesApply] = ("Apply", "写入控制器"),
        [TextId.TablesReload] = ("Reload", "重新读取"),
        [TextId.HistoryRefresh] = ("Refresh", "刷新"),
        [TextId.JobHistoryLabel] = ("Jobs started here", "本机启动的作业"),
        [TextId.AlarmHistoryLabel] = ("Alarm history", "报警历史"),
        [TextId.ModeStopped] = ("Stopped", "已停止"),
        [TextId.ModeAlarm] = ("Alarm", "报警"),
        [TextId.SpindleReadout] = ("{0} rpm (S{1})", "{0} 转/分（编程 S{1}）"),
        [TextId.MachineSummary] = ("{0} | {1} | Feed {2} mm/min (programmed {3}) | Override {4} % | Spindle {5} | {6}", "{0} | {1} | 进给 {2} mm/min（编程 {3}）| 倍率 {4} % | 主轴 {5} | {6}"),
        [TextId.AlarmBanner] = ("ALARM: {0}", "报警：{0}"),
        [TextId.ConsoleDone] = ("Done: {0}", "完成：{0}"),
        [TextId.ConsoleRefused] = ("Refused: {0}", "被拒绝：{0}"),
        [TextId.ConnectFirst] = ("Connect to a controller first.", "请先连接控制器。"),
        [TextId.TableNumber] = ("{0} {1}: '{2}' is not a number", "{0} {1}：“{2}”不是数字"),
        [TextId.TableRange] = ("{0} {1}: {2} is out of range ({3} to {4})", "{0} {1}：{2} 超出范围（{3} 至 {4}）"),
        [TextId.TableNotWritten] = ("Not written: {0}", "未写入：{0}"),
        [TextId.TableNoChanges] = ("No changes to write.", "没有需要写入的更改。"),
        [TextId.TableWritten] = ("Written: {0}", "已写入：{0}"),
        [TextId.ConfirmTablesTitle] = ("Write to the controller", "写入控制器"),
        [TextId.ConfirmTablesText] = ("These values change on the controller:\n\n{0}\n\nWrite them?", "以下数值将写入控制器：\n\n{0}\n\n是否写入？"),
        [TextId.ColTable] = ("Table", "坐标系"),
        [TextId.ColTool] = ("Tool", "刀号"),
        [TextId.ColLength] = ("Length", "长度"),
        [TextId.ColRadius] = ("Radius", "半径"),
        [TextId.ColLengthWear] = ("Length wear", "长度磨损"),
        [TextId.ColRadiusWear] = ("Radius wear", "半径磨损"),
        [TextId.JobRow] = ("{5:HH:mm:ss}  job {0}  {1}  {2}  {3}  line {4}", "{5:HH:mm:ss}  作业 {0}  {1}  {2}  {3}  第 {4} 行"),
        [TextId.AlarmRow] = ("{0:HH:mm:ss}  alarm: {1}{2}", "{0:HH:mm:ss}  报警：{1}{2}"),
        [TextId.AlarmCleared] = ("  (cleared {0:HH:mm:ss})", "  （{0:HH:mm:ss} 已清除）"),
        [TextId.LibraryLoaded] = ("Library of {0} loaded", "已下载 {0} 的程序库"),
        [TextId.TabStore] = ("Store", "程序库"),
        [TextId.StoreLocation] = ("Store: {0}", "数据库：{0}"),
        [TextId.StorePrograms] = ("Programs in the store", "库中的程序"),
        [TextId.StoreRefresh] = ("Refresh", "刷新"),
        [TextId.StoreOpen] = ("Open program", "打开程序"),
        [TextId.StoreColJob] = ("Job", "作业"),
        [TextId.StoreColProgram] = ("Program", "程序"),
        [TextId.StoreColStation] = ("Station", "工位"),
        [TextId.StoreColMachine] = ("Machine", "机床"),
        [TextId.StoreColStarted] = ("Started", "开始"),
        [TextId.StoreColEnded] = ("Ended", "结束"),
        [TextId.StoreColOutcome] = ("Outcome", "结果"),
        [TextId.StoreColBlocks] = ("Blocks", "程序段"),
        [TextId.StoreColId] = ("Id", "编号"),
        [TextId.StoreColName] = ("Name", "名称"),
        [TextId.StoreColProfile] = ("Profile", "机床配置"),
        [TextId.StoreColErrors] = ("Errors", "错误"),
        [TextId.StoreSummary] = ("{0} jobs, {1} programs in {2}", "{2} 中有 {0} 个作业、{1} 个程序"),
        [TextId.StoreSelectFirst] = ("Select a program first.", "请先选择一个程序。"),
        [TextId.StoreHasErrors] = ("program {0} ({1}) has {2} errors: it cannot run (pmacstream programs show {0})", "程序 {0}（{1}）有 {2} 个错误，不能运行（pmacstream programs show {0}）"),
        [TextId.StoreOpened] = ("opened program {0} ({1})", "已打开程序 {0}（{1}）"),
        [TextId.StoreOpenedUnder] = ("opened program {0} ({1}) under {2}", "已打开程序 {0}（{1}），机床配置 {2}"),
        [TextId.StoreOutcomeRunning] = ("running", "运行中"),
        [TextId.StoreOutcomeCompleted] = ("completed", "已完成"),
        [TextId.StoreOutcomeAborted] = ("aborted", "已中止"),
        [TextId.StoreOutcomeInterrupted] = ("interrupted", "已中断"),
        [TextId.StoreOutcomeAlarm] = ("alarm", "报警"),
    };

    /// <summary>The text for an id in a language (English when a translation is missing).</summary>
    public static string Get(TextId id, HmiLanguage language)
    {
        if (!Table.TryGetValue(id, out var t))
        {
            return id.ToString();
        }

        return language == HmiLanguage.Chinese && t.Zh.Length > 0 ? t.Zh : t.En;
    }

    /// <summary>True when the table has a text for the id (tests check that none is missing).</summary>
    internal static bool IsDefined(TextId id) => Table.ContainsKey(id);

    /// <summary>Formats the text for an id with arguments (invariant number formatting).</summary>
    public static string Format(TextId id, HmiLanguage language, params object[] args) =>
        string.Format(CultureInfo.InvariantCulture, Get(id, language), args);

    /// <summary>Every id with its text in a language: what the view applies to its controls.</summary>
    public static IReadOnlyDictionary<TextId, string> All(HmiLanguage language) =>
        Enum.GetValues<TextId>().ToDictionary(id => id, id => Get(id, language));

    /// <summary>The culture diagnostics should be written in for a language.</summary>
    public static CultureInfo Culture(HmiLanguage language) =>
        CultureInfo.GetCultureInfo(language == HmiLanguage.Chinese ? "zh-CN" : "en-US");
}
