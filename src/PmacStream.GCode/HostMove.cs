namespace PmacStream.GCode;

/// <summary>What one step of a canned cycle or a reference return does on the machine.</summary>
public enum HostMoveKind : byte
{
    /// <summary>Rapid to <see cref="HostMove.Target"/> (work coordinates in force).</summary>
    Rapid,

    /// <summary>Feed to <see cref="HostMove.Target"/> at the feed in force.</summary>
    Feed,

    /// <summary>Dwell for <see cref="HostMove.Seconds"/>.</summary>
    Dwell,

    /// <summary>Rapid to <see cref="HostMove.Target"/> in machine coordinates (a reference position), on the axes <see cref="HostMove.Axes"/> names.</summary>
    MachineRapid,

    /// <summary>Spindle stop (M05), before a rapid out of a boring cycle's hole.</summary>
    SpindleStop,

    /// <summary>Spindle clockwise (M03).</summary>
    SpindleForward,

    /// <summary>Spindle counter-clockwise (M04): a tapping cycle's way out, or its way in for left-hand taps.</summary>
    SpindleReverse,

    /// <summary>Spindle orientation (M19) before a fine-boring shift.</summary>
    SpindleOrient,
}

/// <summary>
/// One step the interpreter makes of a block that the host expands into plain moves (canned cycles, reference
/// returns): <see cref="Target"/> is in machine coordinates, as every interpreter position is.
/// </summary>
/// <param name="Kind">What the step does.</param>
/// <param name="Target">Where it ends, machine coordinates (unchanged for spindle steps and dwells).</param>
/// <param name="Seconds">A dwell's time.</param>
/// <param name="Axes">For <see cref="HostMoveKind.MachineRapid"/>: which of X, Y, Z move (bits 0-2).</param>
public readonly record struct HostMove(HostMoveKind Kind, Point3 Target, double Seconds = 0, int Axes = 7);
