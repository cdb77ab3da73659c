using System.Globalization;

namespace PmacStream.GCode;

/// <summary>
/// Diagnostic message texts by code and culture. English is built in; Simplified Chinese comes from the same table
/// so that a missing translation falls back to English instead of failing.
/// </summary>
public static class DiagnosticText
{
    private static readonly Dictionary<string, (string En, string Zh)> Texts = new()
    {
        [DiagnosticCodes.IllegalCharacter] = ("illegal character '{0}': expected an address letter A-Z, '(' or ';'", "非法字符 '{0}'：应为地址字母 A-Z、'(' 或 ';'"),
        [DiagnosticCodes.MalformedNumber] = ("malformed number after '{0}': expected digits such as 1, -2.5 or .5", "'{0}' 后的数值格式错误：应为数字，如 1、-2.5 或 .5"),
        [DiagnosticCodes.UnclosedComment] = ("unclosed comment: expected ')' before the end of the line", "注释未闭合：行尾之前应有 ')'"),
        [DiagnosticCodes.LineTooLong] = ("line longer than {0} bytes: the rest of the line is ignored", "行长度超过 {0} 字节：其余部分被忽略"),
        [DiagnosticCodes.LowercaseLetter] = ("lowercase letter '{0}': accepted, but write address letters in upper case", "小写字母 '{0}'：可以接受，但地址字母应大写"),
        [DiagnosticCodes.UnknownGCode] = ("unknown G code G{0}: not in machine profile '{1}'", "不可识别的 G 代码 G{0}：机床配置 '{1}' 中没有"),
        [DiagnosticCodes.UnknownMCode] = ("unknown M code M{0}: not in machine profile '{1}'", "不可识别的 M 代码 M{0}：机床配置 '{1}' 中没有"),
        [DiagnosticCodes.NegativeValue] = ("value out of range: {0}{1} must not be negative", "参数值超出范围：{0}{1} 不能为负"),
        [DiagnosticCodes.ToolOutOfRange] = ("value out of range: T{0}: expected a whole tool number from 0 to {1}", "参数值超出范围：T{0}：刀具号应为 0 到 {1} 的整数"),
        [DiagnosticCodes.DecimalCode] = ("value out of range: {0}{1}: the machine profile knows no {0} code with decimals like this", "参数值超出范围：{0}{1}：机床配置中没有这种带小数的 {0} 代码"),
        [DiagnosticCodes.ModalGroupConflict] = ("{0}{1} and {0}{2} are both in modal group {3}: only one code of a group per block", "同一组模态代码重用：{0}{1} 与 {0}{2} 同属模态组 {3}，每段只能有一个"),
        [DiagnosticCodes.NoFunction] = ("block has no effective function code: expected a G, M, F, S, T, H, D or axis word", "此段程序无有效功能代码：应有 G、M、F、S、T、H、D 或坐标字"),
        [DiagnosticCodes.DuplicateWord] = ("word {0} appears twice in the block (first at column {1})", "同一段中字 {0} 出现两次（第一次在第 {1} 列）"),
        [DiagnosticCodes.MotionWithoutAxes] = ("G{0} without axis words: expected an end point such as X, Y or Z", "G{0} 没有坐标字：应给出终点，如 X、Y 或 Z"),
        [DiagnosticCodes.ArcWithoutCenter] = ("arc G{0} without R or {1}: expected the radius or the centre offset for plane G{2}", "圆弧 G{0} 没有 R 或 {1}：平面 G{2} 需要半径或圆心偏移"),
        [DiagnosticCodes.ArcRadiusMismatch] = ("arc end point is not on the circle: start radius {0}, end radius {1} (the profile's arc tolerance: {2} and {3} % of the radius)", "圆弧终点不在圆上：起点半径 {0}，终点半径 {1}（机床配置的圆弧允差：{2} 且半径的 {3} %）"),
        [ArcRadiusKey] = ("arc radius R {0} is shorter than half the chord ({1}) by more than the profile's tolerance {2}: the end point cannot be reached", "圆弧半径 R {0} 比弦长的一半（{1}）短，超过机床配置的允差 {2}：无法到达终点"),
        [DiagnosticCodes.ArcRoundedOffCircle] = ("arc end point is {0} off its circle (start radius {1}, end radius {2}): within the arc tolerance, but more than rounding to the program's last decimal explains ({3}); the controller runs a spiral to the programmed end point", "圆弧终点偏离圆 {0}（起点半径 {1}，终点半径 {2}）：在圆弧允差之内，但超过程序末位小数的舍入误差（{3}）；控制器以螺旋线走到编程终点"),
        [DiagnosticCodes.FeedMoveWithoutFeed] = ("feed move G{0} without a feed rate: expected an F word greater than 0 before or in this block", "进给运动 G{0} 没有进给速度：本段或之前应有大于 0 的 F 字"),
        [DiagnosticCodes.UnsupportedLetter] = ("address letter '{0}' is not used by machine profile '{1}' (letters {2})", "机床配置 '{1}' 不使用地址字母 '{0}'（可用字母 {2}）"),
        [DiagnosticCodes.EmptyProgram] = ("empty program: the file holds no blocks", "空程序：文件中没有程序段"),
        [DiagnosticCodes.NulByte] = ("NUL byte: this looks like a binary file, not G-code text", "NUL 字节：这像是二进制文件，不是 G 代码文本"),
        [DiagnosticCodes.Utf16File] = ("the file is UTF-16 encoded: save it as ASCII or UTF-8", "文件为 UTF-16 编码：请另存为 ASCII 或 UTF-8"),
        [DiagnosticCodes.NoProgramNumber] = ("the program has no program number: expected an O word such as O1001", "此程序没有指定程序号：应有 O 字，如 O1001"),
        [DiagnosticCodes.NoSequenceNumber] = ("block has no sequence number while other blocks are numbered", "此程序段没有指定段号（其他程序段有段号）"),
        [DiagnosticCodes.UnusedWord] = ("word {0} is not used by this block and is ignored", "指令后续参数不匹配：字 {0} 在本段中无用，将被忽略"),
        [DiagnosticCodes.MissingWord] = ("{0} without {1}: {2}", "{0} 缺少 {1}：{3}"),
        [DiagnosticCodes.NestedComment] = ("'(' inside a comment: comments do not nest", "注释中出现 '('：注释不能嵌套"),
        [DiagnosticCodes.RequiredWordMissing] = ("{0} without {1}: {2}", "{0} 缺少 {1}：{3}"),
        [DiagnosticCodes.ValueNotAllowed] = ("value out of range: {0}{1} with {2}: expected {3}", "参数值超出范围：{2} 的 {0}{1}：应为 {3}"),
        [DiagnosticCodes.NoMotionMode] = ("axis words but no motion mode in force: expected G00, G01, G02 or G03 first", "有坐标字但没有有效的运动方式：应先指定 G00、G01、G02 或 G03"),
        [DiagnosticCodes.NotYetOnController] = ("{0} ({1}) is accepted by profile '{2}' but the controller cannot run it yet: a job using it is refused", "机床配置 '{2}' 接受 {0}，但控制器尚不能执行它：使用它的作业将被拒绝"),
        [DiagnosticCodes.NotRunnableInJob] = ("{0} ({1}) cannot run on the controller yet under profile '{2}': the PMAC would skip the code and run the rest of the block", "{0}（{1}）在机床配置 '{2}' 下尚不能在控制器上执行：PMAC 会跳过该代码而执行本段其余部分"),
        [DiagnosticCodes.TextAfterTapeEnd] = ("text after the closing '%' is ignored: the program ends at this line", "结束符 '%' 之后的内容被忽略：程序在此行结束"),
        [OWordKey] = ("'{0}' is a LinuxCNC o-word (subroutine or flow control): this profile does not run o-word subroutines, loops or conditions; expand them in the CAM output (or post for FANUC)", "'{0}' 是 LinuxCNC 的 o-word（子程序或流程控制）：此机床配置不执行 o-word 子程序、循环或条件；请在 CAM 输出中展开（或按 FANUC 后处理）"),
        [DoubleSlashKey] = ("illegal characters '//': a tool-table entry of an older ISO dialect (T1//15.98: tool 1, diameter 15.98), not FANUC syntax; the rest of the line is ignored", "非法字符 '//'：旧式 ISO 方言的刀具表条目（T1//15.98：1 号刀，直径 15.98），不是 FANUC 语法；本行其余部分被忽略"),
        [DiagnosticCodes.TooManyWords] = ("more than {0} words on one line: the rest of the line is not read", "一行中超过 {0} 个字：该行其余部分不再读取"),
        [DiagnosticCodes.TransformNotRunnable] = ("{0} under {1}: {2}", "{1} 下的 {0}：{3}"),
        [DiagnosticCodes.CycleInInverseTime] = ("canned cycle G{0} in inverse time (G93): the cycle's feed moves have no F of their own; program G94 and a feed per minute before the cycle", "反时限进给（G93）下的固定循环 G{0}：循环的进给运动没有自己的 F；请在循环前指定 G94 和每分钟进给"),
        [DiagnosticCodes.RotaryOffset] = ("{0} on rotary axis {1}: offsets on A, B and C are not applied on the controller, so {1} would run at its program value; set the rotary offset at the machine", "旋转轴 {1} 上的 {0}：控制器上不应用 A、B、C 的偏置，{1} 将按程序值运行；请在机床上设定旋转轴偏置"),
        [DiagnosticCodes.NoCutterRadius] = ("{0} without a cutter radius: {1} is not in profile '{2}''s toolRadii", "{0} 没有刀具半径：{1} 不在机床配置 '{2}' 的 toolRadii 中"),
        [DiagnosticCodes.CompensationNotRunnable] = ("{0} under cutter radius compensation: {1}", "刀具半径补偿下的 {0}：{2}"),
        [DiagnosticCodes.CompensationEntryTooShort] = ("cutter radius compensation entry move is not longer than the tool radius ({0} mm)", "刀具半径补偿的引入运动不长于刀具半径（{0} mm）"),
        [DiagnosticCodes.CompensationConcaveCorner] = ("inside corner under cutter radius compensation the compensated tool can't fit in without gouging: the offset paths of the move before and this one do not cross", "刀具半径补偿下的内拐角无法不过切：前一运动与本运动的偏置路径不相交"),
        [HeldTooFarKey] = ("inside corner under cutter radius compensation with more than {1} blocks between it and the XY move it ends (line {0}): the host holds that move and queues at most {1} blocks behind it (Z moves, dwells, codes) until the next XY move decides where it ends; move the XY move nearer, or G40 before the blocks between", "刀具半径补偿下的内拐角与其所结束的 XY 运动（第 {0} 行）之间超过 {1} 个程序段：主机保留该运动，其后最多排队 {1} 个程序段（Z 运动、暂停、代码），直到下一个 XY 运动确定其终点；请把 XY 运动移近，或在中间的程序段之前 G40"),
        [DiagnosticCodes.DialectG10L20] = ("G10 L20 P{0} at line {1} set the extended work offset G54.1 P{0} under profile '{2}' (FANUC), which the program has not selected before this move; under grbl and LinuxCNC G10 L20 P{0} sets work offset P{0} (G54 for P1) so that the position there reads as {3}: a program written for them runs this move off by that offset", "第 {1} 行的 G10 L20 P{0} 在机床配置 '{2}'（FANUC）下设定扩展工件坐标系 G54.1 P{0}，而程序在此运动之前没有选用它；在 grbl 和 LinuxCNC 中 G10 L20 P{0} 设定工件坐标系 P{0}（P1 即 G54），使当时位置读作 {3}：为它们编写的程序此运动将偏移该偏置量"),
        [DiagnosticCodes.DialectDwellUnits] = ("G04 P{0}: FANUC and Haas read P in milliseconds ({1} s), LinuxCNC and grbl in seconds ({0} s); profile '{2}' takes the {3} meaning, and the value looks written for the other: write G04 X in seconds", "G04 P{0}：FANUC 和 Haas 的 P 以毫秒计（{1} 秒），LinuxCNC 和 grbl 以秒计（{0} 秒）；机床配置 '{2}' 按 {3} 的含义执行，而此值像是为另一方言编写：请用 G04 X 指定秒数"),
        [DiagnosticCodes.DialectG10L2P0] = ("G10 L2 P0 has two meanings: FANUC sets the external work offset, added to every work coordinate system; LinuxCNC and grbl set the work offset in force ({2}); profile '{0}' takes the {1} meaning", "G10 L2 P0 有两种含义：FANUC 设定外部工件坐标偏置，加到所有工件坐标系上；LinuxCNC 和 grbl 设定当前生效的工件坐标系（{2}）；机床配置 '{0}' 按 {1} 的含义执行"),
        [DiagnosticCodes.DialectReturn] = ("{0} without axis words: Haas, LinuxCNC and grbl send every axis to the {0} position; FANUC moves no axis, and neither does this host under profile '{1}': name the axes ({0} G91 Z0)", "没有坐标字的 {0}：Haas、LinuxCNC 和 grbl 将所有轴送回 {0} 位置；FANUC 不移动任何轴，机床配置 '{1}' 下本主机也不移动：请写出轴（{0} G91 Z0）"),
        [ReturnThroughWorkKey] = ("{0} in absolute mode (G90) first moves to the intermediate point {1} in work coordinates, then to the reference position (FANUC, LinuxCNC and grbl alike); posts write G91 {0} Z0 to go straight home: a program that means that drives the tool to the intermediate point first", "绝对方式（G90）下的 {0} 先移动到工件坐标中的中间点 {1}，再到参考点（FANUC、LinuxCNC 和 grbl 相同）；后处理写 G91 {0} Z0 以直接回参考点：若程序本意如此，刀具会先走到中间点"),
        [DiagnosticCodes.DialectToolChange] = ("M06 with no T word since the last tool change: FANUC, Haas and LinuxCNC change to the tool of the last T word (T{0}); a program written for a control that reads the T after M06 means the T of a later block", "自上次换刀以来没有 T 字的 M06：FANUC、Haas 和 LinuxCNC 换上最后一个 T 字的刀具（T{0}）；为在 M06 之后读取 T 的控制器编写的程序指的是后面程序段的 T"),
        [DiagnosticCodes.DialectG92AtEnd] = ("the G92 shift ({0}) is still in force at program end: LinuxCNC keeps it for the next program (and across restarts) until G92.1; FANUC's reset and this host's next job start without it: end the program with G92.1", "程序结束时 G92 偏移（{0}）仍然有效：LinuxCNC 在 G92.1 之前会为下一个程序（甚至重启后）保留它；FANUC 的复位和本主机的下一个作业则不带它开始：请以 G92.1 结束程序"),
        [UnlistedKey] = ("{0} more not listed (at most {1} a line)", "另有 {0} 条未列出（每行最多 {1} 条）"),
        [SummaryKey] = ("{0} errors, {1} warnings, {2} blocks", "{0} 个错误，{1} 个警告，{2} 个程序段"),
    };

    /// <summary>The key of W012's text for G28/G30 in G90 through an intermediate point that moves.</summary>
    internal const string ReturnThroughWorkKey = "return-through-work";

    /// <summary>The key of E135's text for an inside corner too many blocks after the move it ends (the hold's bound).</summary>
    internal const string HeldTooFarKey = "comp-held-too-far";

    /// <summary>The key of E115's text for an R shorter than half the chord.</summary>
    internal const string ArcRadiusKey = "arc-r";

    /// <summary>The key of E102's text for a LinuxCNC o-word construct (<c>O100 sub</c>), which no profile runs.</summary>
    internal const string OWordKey = "oword";

    /// <summary>The key of E101's argument for <c>//</c> after a word (an older dialect's tool-table line).</summary>
    internal const string DoubleSlashKey = "doubleslash";

    /// <summary>The key of the check's summary line (<c>N errors, M warnings, B blocks</c>) in the table.</summary>
    internal const string SummaryKey = "summary";

    /// <summary>The key of the summary's note on findings counted but not listed (past <see cref="FindingLimits.PerLine"/> on a line).</summary>
    internal const string UnlistedKey = "summary-unlisted";

    private static readonly CultureInfo DefaultCulture = CultureInfo.CurrentUICulture;
    private static readonly AsyncLocal<CultureInfo?> FlowCulture = new();

    /// <summary>
    /// The culture messages are written in; defaults to the current UI culture. Setting it holds for the current
    /// operation (the async flow, and the tasks and threads it starts), not for the whole process: a check run in
    /// Chinese for the HMI, or for <c>pmacstream check --lang zh</c>, does not change the messages of another check
    /// running meanwhile (tests run many at once, and two HMI checks may overlap).
    /// </summary>
    public static CultureInfo Culture
    {
        get => FlowCulture.Value ?? DefaultCulture;
        set => FlowCulture.Value = value;
    }

    /// <summary>True when a message is registered for the code.</summary>
    public static bool IsRegistered(string code) => Texts.ContainsKey(code);

    /// <summary>Registers or replaces a message (the checker adds its codes here).</summary>
    public static void Register(string code, string english, string chinese) => Texts[code] = (english, chinese);

    /// <summary>Formats the message for a code in <see cref="Culture"/>.</summary>
    public static string Format(string code, params object[] args) => Format(Culture, code, args);

    /// <summary>Formats the message for a code in the given culture (zh* gives Simplified Chinese, anything else English).</summary>
    public static string Format(CultureInfo culture, string code, params object[] args)
    {
        if (!Texts.TryGetValue(code, out var t))
        {
            return code;
        }

        var zh = culture.Name.StartsWith("zh", StringComparison.OrdinalIgnoreCase);
        return string.Format(CultureInfo.InvariantCulture, zh ? t.Zh : t.En, args);
    }
}
