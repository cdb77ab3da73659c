namespace PmacStream.IntegrationTests.Plc;

/// <summary>
/// What samples/plc/sand-mould-spindle.ladder must do, written as the machine's operating rules rather than as
/// rungs. Inputs: ESTOP_OK 0, AIR_OK 1, DOOR_CLOSED 2, SP_FAULT 3, SP_START 4, SP_STOP 5, CL_START 6, CL_STOP 7,
/// RESET 8. Outputs: DUST 0, READY_LAMP 1, SPINDLE 2, COOLANT 3, ALARM_LAMP 4.
/// </summary>
internal readonly record struct SandMould(bool Alarm, bool Spindle, bool Coolant)
{
    public const int EstopOk = 1, AirOk = 2, DoorClosed = 4, SpFault = 8, SpStart = 16, SpStop = 32, ClStart = 64, ClStop = 128, Reset = 256;
    public const int Healthy = EstopOk | AirOk | DoorClosed;
    public const int InputCount = 9;

    public const long Dust = 1, Ready = 2, SpindleOut = 4, CoolantOut = 8, AlarmLamp = 16;

    public static bool ChainOk(long inputs) => (inputs & (Healthy | SpFault)) == Healthy;

    public SandMould Step(long inputs)
    {
        bool Held(int bit) => (inputs & bit) != 0;

        // 1. Any break of the safety chain latches the alarm; only RESET with a healthy chain clears it.
        var alarm = !ChainOk(inputs) || (Alarm && !Held(Reset));

        // 2. The spindle runs only without alarm; stop wins over start; once running it holds.
        var spindle = !alarm && !Held(SpStop) && (Spindle || Held(SpStart));

        // 3. Coolant mist only while the spindle runs; off wins over on; it holds.
        var coolant = spindle && !Held(ClStop) && (Coolant || Held(ClStart));
        return new SandMould(alarm, spindle, coolant);
    }

    public long Outputs =>
        (Spindle ? Dust | SpindleOut : 0) | (Coolant ? CoolantOut : 0) | (Alarm ? AlarmLamp : 0) | (!Alarm && !Spindle ? Ready : 0);
}

/// <summary>Drives a rig with input sequences and checks it against <see cref="SandMould"/> and the safety rules.</summary>
internal sealed class SandMouldChecker(IPlcRig rig)
{
    private long _inputs;
    private long _outputs;
    private SandMould _model;

    public int Steps { get; private set; }

    public int SpindleStarts { get; private set; }

    public int AlarmsLatched { get; private set; }

    public int AlarmsCleared { get; private set; }

    public int CoolantStarts { get; private set; }

    public List<string> Trace { get; } = [];

    public void PowerUp(long inputs)
    {
        Trace.Clear();
        _model = default;
        _outputs = 0;
        Apply(inputs, "power up");
    }

    public long Outputs => _outputs;

    public void Apply(long inputs, string what)
    {
        var before = _outputs;
        _inputs = inputs;
        rig.SetInputs(inputs);
        rig.Scan();
        _outputs = rig.Outputs;
        _model = _model.Step(inputs);
        Steps++;
        Trace.Add($"{what} -> inputs {Convert.ToString(inputs, 2).PadLeft(9, '0')} outputs {Convert.ToString(_outputs, 2).PadLeft(5, '0')}");
        bool On(long o, long bit) => (o & bit) != 0;
        Check(_outputs == _model.Outputs, $"the rules give outputs {Convert.ToString(_model.Outputs, 2).PadLeft(5, '0')}");
        Check(!On(_outputs, SandMould.SpindleOut) || SandMould.ChainOk(inputs), "the spindle never runs with the safety chain broken");
        Check(On(_outputs, SandMould.Dust) == On(_outputs, SandMould.SpindleOut), "dust extraction runs exactly when the spindle runs");
        Check(!On(_outputs, SandMould.CoolantOut) || On(_outputs, SandMould.SpindleOut), "coolant only with the spindle");
        Check(SandMould.ChainOk(inputs) || On(_outputs, SandMould.AlarmLamp), "a broken chain shows the alarm lamp");
        if (On(_outputs, SandMould.SpindleOut) && !On(before, SandMould.SpindleOut))
        {
            Check((inputs & SandMould.SpStart) != 0, "the spindle starts only on a start press (no automatic restart)");
            SpindleStarts++;
        }

        if (On(_outputs, SandMould.CoolantOut) && !On(before, SandMould.CoolantOut))
        {
            CoolantStarts++;
        }

        if (On(_outputs, SandMould.AlarmLamp) && !On(before, SandMould.AlarmLamp))
        {
            AlarmsLatched++;
        }

        if (!On(_outputs, SandMould.AlarmLamp) && On(before, SandMould.AlarmLamp))
        {
            Check((inputs & SandMould.Reset) != 0 && SandMould.ChainOk(inputs), "the alarm clears only by RESET with a healthy chain");
            AlarmsCleared++;
        }
    }

    public void Toggle(int bit, string what) => Apply(_inputs ^ bit, what);

    private void Check(bool ok, string rule)
    {
        if (!ok)
        {
            throw new Xunit.Sdk.XunitException($"{rule}; trace:\n  " + string.Join("\n  ", Trace.TakeLast(12)));
        }
    }
}
