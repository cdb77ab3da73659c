namespace PmacStream.Preparation;

/// <summary>
/// The machine I/O M codes that are plain outputs (Haas and FANUC: through-spindle coolant, rotary axis brakes, chip
/// conveyor, through-tool air blast, air gun): each routine sets the output's M-variable (<see cref="Prog1000Options"/>)
/// and nothing else. Codes that switch something off, clamp a brake or turn the conveyor round start with
/// <c>DWELL0</c>, so the moves ahead of them have run first (lookahead would otherwise set the output while earlier
/// moves are still running); codes that switch something on do not wait, as flood coolant (M08) does not. None waits
/// for an input: whatever confirms the output (a coolant pressure switch, a brake's released switch) is the
/// machine's own logic.
/// </summary>
internal static class MachineOutputRoutines
{
    /// <summary>The routine of M code <paramref name="key"/> (the code times ten), or null when it is not a plain output.</summary>
    public static string? M(int key, Prog1000Options o) => key switch
    {
        880 => $"{o.ThroughSpindleCoolant}=1",
        890 => $"DWELL0 {o.ThroughSpindleCoolant}=0",
        // A brake clamps an axis at rest, and is released only once the moves before have ended.
        100 => $"DWELL0 {o.FourthAxisBrake}=1",
        110 => $"DWELL0 {o.FourthAxisBrake}=0",
        120 => $"DWELL0 {o.FifthAxisBrake}=1",
        130 => $"DWELL0 {o.FifthAxisBrake}=0",
        310 => $"{o.ChipConveyorReverse}=0 {o.ChipConveyor}=1",
        320 => $"DWELL0 {o.ChipConveyorReverse}=1 {o.ChipConveyor}=1",
        330 => $"DWELL0 {o.ChipConveyor}=0",
        730 => $"{o.ThroughToolAir}=1",
        740 => $"DWELL0 {o.ThroughToolAir}=0",
        830 => $"{o.AirGun}=1",
        840 => $"DWELL0 {o.AirGun}=0",
        _ => null,
    };
}
