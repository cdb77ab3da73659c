using System.Globalization;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// The library routines that give work offsets, tool lengths, machine coordinates and the tool change their meaning
/// on a Turbo PMAC. The coordinate system's axis transformation matrix carries the whole offset from program to
/// machine coordinates as its displacement: one routine composes it from the modal state (work offset from the table
/// + G52 + G92 + tool length on Z) and applies it with <c>ADIS</c>, which renames the current position and moves
/// nothing, so the moves of the rotary buffer stay the program's own words. Routines that take words read them with
/// <c>READ</c> (values in Q101-Q126, which letters came in Q100's bits).
/// </summary>
internal static class LibraryRoutines
{
    /// <summary>Composes the displacement and applies it (PROG 1000, also <c>CALL1000.991</c>).</summary>
    public const int Recompose = 99100;

    /// <summary>Applies the tool length of the length mode in force, then <see cref="Recompose"/>.</summary>
    public const int ApplyToolLength = 99200;

    /// <summary>Machine coordinates: zero displacement and absolute mode, for one block.</summary>
    public const int MachineCoordinates = 99300;

    /// <summary>The power-on state: G54, no shifts, no tool length, G90 (program end, and the host's <c>G99.9</c>).</summary>
    public const int PowerOn = 99900;

    /// <summary>Back from machine coordinates after a G53 block (the host's <c>G53.9</c>).</summary>
    public const int BackFromMachine = 53900;

    /// <summary>The move before ends at rest (the host's <c>G09.9</c> in exact stop mode, where the profile has no G09 of its own).</summary>
    public const int ExactStop = 9900;

    private const long BitX = 1L << 23;
    private const long BitY = 1L << 24;
    private const long BitZ = 1L << 25;

    /// <summary>The library's own labels in PROG 1000, with what each does.</summary>
    public static IEnumerable<(int Label, string Body, string What)> Private(MachineProfile profile, Prog1000Options o)
    {
        var m = o.Map;
        foreach (var label in new[] { Recompose, ApplyToolLength, MachineCoordinates, PowerOn, BackFromMachine, ExactStop })
        {
            if (profile.Find('G', label / 1000.0) is { } clash)
            {
                throw new InvalidDataException($"profile '{profile.Name}': {clash.Code} would take the library's own label N{label}");
            }
        }

        var w = m.WorkOffsets;
        // FANUC's external work offset (G10 L2 P0) is index 0 of the table, added to whichever offset is selected.
        string Ext(int axis) => profile.ExternalWorkOffset ? $"+P{w + axis}" : string.Empty;
        yield return (Recompose,
            $"{m.Q(14)}=P({w}+{m.Q(0)}*3){Ext(0)}+{m.Q(1)}+{m.Q(4)} " +
            $"{m.Q(15)}=P({w + 1}+{m.Q(0)}*3){Ext(1)}+{m.Q(2)}+{m.Q(5)} {m.Q(16)}=P({w + 2}+{m.Q(0)}*3){Ext(2)}+{m.Q(3)}+{m.Q(6)}+{m.Q(7)} TSEL{m.Matrix} ADIS{m.State + 14}",
            profile.ExternalWorkOffset
                ? "compose the displacement: work offset + external offset (index 0) + G52 + G92 + tool length on Z, applied with ADIS (renames, moves nothing)"
                : "compose the displacement: work offset + G52 + G92 + tool length on Z, applied with ADIS (renames, moves nothing)");
        yield return (ApplyToolLength,
            $"{m.Q(7)}=0\r\nIF({m.Q(9)}=43) {m.Q(7)}=P({m.ToolLengths}+{m.Q(8)})\r\nIF({m.Q(9)}=44) {m.Q(7)}=-P({m.ToolLengths}+{m.Q(8)})\r\nGOSUB{Recompose}",
            "tool length of offset H from the tool table, + for G43, - for G44, 0 for G49");
        yield return (MachineCoordinates,
            $"{m.Q(13)}=1 {m.Q(14)}=0 {m.Q(15)}=0 {m.Q(16)}=0 TSEL{m.Matrix} ADIS{m.State + 14} ABS",
            "machine coordinates for one block: no displacement, absolute");
        yield return (BackFromMachine,
            $"{m.Q(13)}=0 GOSUB{Recompose}\r\nIF({m.Q(10)}=91) INC\r\nIF({m.Q(11)}=0) RAPID\r\nIF({m.Q(11)}=1) LINEAR\r\nIF({m.Q(11)}=2) CIRCLE1\r\nIF({m.Q(11)}=3) CIRCLE2",
            "G53.9 (sent by the host after a G53 block): back to work coordinates, distance and motion modes");
        yield return (ExactStop, "DWELL0",
            "G09.9 (sent by the host after each move in exact stop mode where the profile has no G09): the move ends at rest");
        yield return (PowerOn,
            $"{m.Q(0)}=1 {m.Q(1)}=0 {m.Q(2)}=0 {m.Q(3)}=0 {m.Q(4)}=0 {m.Q(5)}=0 {m.Q(6)}=0 {m.Q(8)}=0 {m.Q(9)}=0 {m.Q(10)}=90 {m.Q(13)}=0 ABS GOSUB{ApplyToolLength}",
            "power-on state: G54, no G52/G92 shift, G49, G90");
    }

    /// <summary>The G codes whose meaning this library gives (null: the built-in motion and mode routines).</summary>
    public static string? G(int key, MachineProfile profile, Prog1000Options o)
    {
        var m = o.Map;
        string Select(int index) => $"{m.Q(0)}={index.ToString(CultureInfo.InvariantCulture)} GOSUB{Recompose}";
        return key switch
        {
            0 => $"RAPID {m.Q(11)}=0",
            10 => $"LINEAR {m.Q(11)}=1",
            20 => $"CIRCLE1 {m.Q(11)}=2",
            30 => $"CIRCLE2 {m.Q(11)}=3",
            900 => $"ABS {m.Q(10)}=90",
            910 => $"INC {m.Q(10)}=91",
            >= 540 and <= 590 when key % 10 == 0 => Select((key - 530) / 10),
            591 or 592 or 593 => Select(key - 584),
            541 => $"READ(P) {m.Q(0)}=9+Q116 GOSUB{Recompose}",
            430 or 440 => $"READ(H)\r\nIF(Q100&128>0) {m.Q(8)}=Q108\r\n{m.Q(9)}={key / 10} GOSUB{ApplyToolLength}",
            490 => $"{m.Q(9)}=0 GOSUB{ApplyToolLength}",
            520 => Shift(1, m),
            920 => Shift(4, m),
            921 or 922 => $"{m.Q(4)}=0 {m.Q(5)}=0 {m.Q(6)}=0 GOSUB{Recompose}",
            530 => $"GOSUB{MachineCoordinates}",
            // The host sends G10 as the resulting table entry: L2 P<index> X Y Z (work offset), L1 P<H> Z (tool length).
            100 => "READ(L,P,X,Y,Z)\r\n" +
                   $"IF(Q112=2 AND Q100&{BitX}>0) P({m.WorkOffsets}+Q116*3)=Q124\r\n" +
                   $"IF(Q112=2 AND Q100&{BitY}>0) P({m.WorkOffsets + 1}+Q116*3)=Q125\r\n" +
                   $"IF(Q112=2 AND Q100&{BitZ}>0) P({m.WorkOffsets + 2}+Q116*3)=Q126\r\n" +
                   $"IF(Q112=1 AND Q100&{BitZ}>0) P({m.ToolLengths}+Q116)=Q126\r\n" +
                   $"GOSUB{ApplyToolLength}",
            _ => null,
        };
    }

    /// <summary>The M codes whose meaning this library gives, machine outputs among them (null: the built-in spindle and coolant outputs).</summary>
    public static string? M(int key, MachineProfile profile, Prog1000Options o)
    {
        var m = o.Map;
        var stop = o.ProgramStops ? " STOP" : string.Empty;
        return key switch
        {
            // DWELL0 ends lookahead so the stop comes after the moves before it; STOP leaves the program where it is and
            // the run command continues after it. M01 asks the optional-stop switch the host sets (a one-line IF, so RET
            // goes on a line of its own).
            0 => "DWELL0" + stop,
            10 => o.ProgramStops ? $"DWELL0\r\nIF ({o.OptionalStop}=1) STOP" : "DWELL0",
            20 or 300 => $"DWELL0 {o.SpindleOn}=0 {o.Coolant}=0 {o.MistCoolant}=0 CALL1000.{PowerOn / 100}",
            30 => $"DWELL0 {o.SpindleOrient}=0 {o.SpindleReverse}=0 {o.SpindleOn}=1",
            40 => $"DWELL0 {o.SpindleOrient}=0 {o.SpindleReverse}=1 {o.SpindleOn}=1",
            70 => $"{o.MistCoolant}=1",
            90 => $"DWELL0 {o.Coolant}=0 {o.MistCoolant}=0",
            190 => SpindleOrient(profile, o),
            60 => "READ(T) DWELL0\r\n" + (o.ToolChangeHook ?? DefaultToolChange(profile, o) + stop) + $"\r\n{m.Q(12)}=Q120",
            _ => MachineOutputRoutines.M(key, o),
        };
    }

    /// <summary>
    /// M19: reads the words the profile's M19 takes, so none is left to run as a statement, and passes the angle
    /// (R; P where the code takes no Q, as Haas's whole degrees) and LinuxCNC's direction P to the orientation logic
    /// before it switches the orientation on. LinuxCNC's Q (seconds to wait for the orientation) is read: the routine
    /// does not wait for an orientation-done input.
    /// </summary>
    private static string SpindleOrient(MachineProfile profile, Prog1000Options o)
    {
        var words = profile.Find('M', 19)?.Words ?? string.Empty;
        var set = $"DWELL0 {o.SpindleOn}=0 {o.SpindleOrientAngle}=0";
        if (words.Length == 0)
        {
            return $"{set} {o.SpindleOrient}=1";
        }

        var read = $"READ({string.Join(',', words.ToCharArray())})\r\n{set}";
        var pIsDirection = words.Contains('Q');
        if (pIsDirection)
        {
            read += $" {o.SpindleOrientDirection}=0\r\nIF(Q100&{Bit('P')}>0) {o.SpindleOrientDirection}=Q116";
        }
        else if (words.Contains('P'))
        {
            read += $"\r\nIF(Q100&{Bit('P')}>0) {o.SpindleOrientAngle}=Q116";
        }

        if (words.Contains('R'))
        {
            read += $"\r\nIF(Q100&{Bit('R')}>0) {o.SpindleOrientAngle}=Q118";
        }

        return $"{read}\r\n{o.SpindleOrient}=1";
    }

    /// <summary>The bit of Q100 that <c>READ</c> sets when letter <paramref name="c"/> came (A is bit 0).</summary>
    private static long Bit(char c) => 1L << (c - 'A');

    /// <summary>Spindle off, to the tool change position in machine coordinates (Z first) when the machine has one.</summary>
    private static string DefaultToolChange(MachineProfile profile, Prog1000Options o)
    {
        var m = o.Map;
        var spindleOff = $"{o.SpindleOn}=0 {o.Coolant}=0 {o.MistCoolant}=0";
        if (profile.ToolChangePosition is null)
        {
            return spindleOff;
        }

        var p = m.ToolChangePosition;
        return $"{spindleOff} CALL1000.{MachineCoordinates / 100} RAPID Z(P{p + 2})\r\nX(P{p}) Y(P{p + 1})\r\nCALL1000.{BackFromMachine / 100}";
    }

    private static string Shift(int first, LibraryMap m) =>
        "READ(X,Y,Z)\r\n" +
        $"IF(Q100&{BitX}>0) {m.Q(first)}=Q124\r\n" +
        $"IF(Q100&{BitY}>0) {m.Q(first + 1)}=Q125\r\n" +
        $"IF(Q100&{BitZ}>0) {m.Q(first + 2)}=Q126\r\n" +
        $"GOSUB{Recompose}";
}
