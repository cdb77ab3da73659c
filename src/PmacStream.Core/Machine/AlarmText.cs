namespace PmacStream.Machine;

/// <summary>
/// The alarms the console reads from a motor's status word, each with a stable code and its text in English and
/// Simplified Chinese (the HMI's two languages).
/// </summary>
public static class AlarmText
{
    /// <summary>Positive end (hardware) limit input on.</summary>
    public const string PlusLimit = "limit+";

    /// <summary>Negative end (hardware) limit input on.</summary>
    public const string MinusLimit = "limit-";

    /// <summary>Stopped on a software limit (Ixx13/Ixx14): the position-limit stop with no hardware input on.</summary>
    public const string SoftwareLimit = "software-limit";

    /// <summary>Killed on the fatal following error limit (Ixx11).</summary>
    public const string FatalFollowingError = "fatal-following-error";

    /// <summary>Killed by an amplifier fault.</summary>
    public const string AmplifierFault = "amp-fault";

    /// <summary>Following error above the warning limit (Ixx12): motion goes on.</summary>
    public const string WarningFollowingError = "warning-following-error";

    /// <summary>Open loop (killed) without a fault bit: another motor's fault killed it, or a K.</summary>
    public const string MotorKilled = "motor-killed";

    /// <summary>Decodes every alarm a motor's status carries, in the language given (<c>en</c>, <c>zh-CN</c>).</summary>
    public static IReadOnlyList<MachineAlarm> Decode(MotorWord w, int motor, string axis, string language = "en")
    {
        var list = new List<MachineAlarm>();
        void Add(string code, AlarmSeverity severity) => list.Add(new MachineAlarm(code, motor, axis, Text(code, axis, motor, language), severity));
        if (w.PlusLimit)
        {
            Add(PlusLimit, AlarmSeverity.Alarm);
        }

        if (w.MinusLimit)
        {
            Add(MinusLimit, AlarmSeverity.Alarm);
        }

        if (w.StoppedOnLimit && !w.PlusLimit && !w.MinusLimit)
        {
            Add(SoftwareLimit, AlarmSeverity.Alarm);
        }

        if (w.AmplifierFault)
        {
            Add(AmplifierFault, AlarmSeverity.Alarm);
        }

        if (w.FatalFollowingError)
        {
            Add(FatalFollowingError, AlarmSeverity.Alarm);
        }
        else if (w.WarningFollowingError)
        {
            Add(WarningFollowingError, AlarmSeverity.Warning);
        }

        if (w.Activated && w.OpenLoop && !w.AmplifierFault && !w.FatalFollowingError)
        {
            Add(MotorKilled, AlarmSeverity.Alarm);
        }

        return list;
    }

    /// <summary>The clear text of an alarm code for an axis and motor.</summary>
    public static string Text(string code, string axis, int motor, string language = "en") =>
        IsChinese(language) ? Chinese(code, axis, motor) : English(code, axis, motor);

    /// <summary>True for the Simplified Chinese texts (<c>zh</c>, <c>zh-CN</c>).</summary>
    public static bool IsChinese(string language) => language.StartsWith("zh", StringComparison.OrdinalIgnoreCase);

    private static string English(string code, string axis, int motor) => code switch
    {
        PlusLimit => $"{axis} axis (motor {motor}) on its positive hardware limit: jog it in the negative direction to move off",
        MinusLimit => $"{axis} axis (motor {motor}) on its negative hardware limit: jog it in the positive direction to move off",
        SoftwareLimit => $"{axis} axis (motor {motor}) stopped on a software limit (Ixx13/Ixx14): jog it back inside",
        FatalFollowingError => $"{axis} axis (motor {motor}) fatal following error: the motor was killed; check the mechanics, then clear the alarm",
        AmplifierFault => $"{axis} axis (motor {motor}) amplifier fault: the motor was killed; check the drive, then clear the alarm",
        WarningFollowingError => $"{axis} axis (motor {motor}) following error above the warning limit (Ixx12)",
        MotorKilled => $"{axis} axis (motor {motor}) is killed (open loop): clear the alarm to enable it",
        _ => $"{axis} axis (motor {motor}): {code}",
    };

    private static string Chinese(string code, string axis, int motor) => code switch
    {
        PlusLimit => $"{axis} 轴（电机 {motor}）压上正向硬限位：请向负方向点动离开",
        MinusLimit => $"{axis} 轴（电机 {motor}）压上负向硬限位：请向正方向点动离开",
        SoftwareLimit => $"{axis} 轴（电机 {motor}）在软限位处停止（Ixx13/Ixx14）：请点动回到行程内",
        FatalFollowingError => $"{axis} 轴（电机 {motor}）跟随误差超限（致命）：电机已断开，检查机械后清除报警",
        AmplifierFault => $"{axis} 轴（电机 {motor}）驱动器故障：电机已断开，检查驱动器后清除报警",
        WarningFollowingError => $"{axis} 轴（电机 {motor}）跟随误差超过警告值（Ixx12）",
        MotorKilled => $"{axis} 轴（电机 {motor}）已断开（开环）：清除报警以使能",
        _ => $"{axis} 轴（电机 {motor}）：{code}",
    };
}
