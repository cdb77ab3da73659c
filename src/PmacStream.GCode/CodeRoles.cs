namespace PmacStream.GCode;

/// <summary>What the interpreter does with a G code: the meaning milling dialects share for its number.</summary>
public enum GRole : byte
{
    /// <summary>A mode or setting the interpreter keeps but that does not change geometry (G40, G64, G94 ...).</summary>
    Mode,

    /// <summary>G00..G03 and the other moves to an end point (G31 skip, G38.x probe, G5.x splines as straight lines).</summary>
    Motion,

    /// <summary>G04 dwell.</summary>
    Dwell,

    /// <summary>A drilling, tapping or boring cycle (G73, G74, G76, G81-G89): modal, one hole per positioning block.</summary>
    Cycle,

    /// <summary>G80: cycles off.</summary>
    CycleCancel,

    /// <summary>G28/G30 (and G27/G29): through the programmed point to a reference position.</summary>
    Reference,

    /// <summary>G53: a move in machine coordinates, this block only.</summary>
    MachineCoordinates,

    /// <summary>Codes whose axis words are data, not a move (G10, G52, G92, G65, G28.1 ...).</summary>
    AxisData,
}

/// <summary>
/// The meaning of code numbers the interpreter relies on, shared by FANUC, Haas, LinuxCNC and grbl milling (a profile
/// decides which of them it has and in which group; this decides what they do).
/// </summary>
public static class CodeRoles
{
    /// <summary>The role of a G code by its key (number x 10).</summary>
    public static GRole OfG(int key) => key switch
    {
        0 or 10 or 20 or 30 => GRole.Motion,
        // Skip (G31), probing (G38.x), splines (G5, G5.1, as straight lines), tool measuring (G37), single-direction
        // positioning (G60), threading (G33): they end at the programmed point.
        310 or 382 or 383 or 384 or 385 or 50 or 51 or 370 or 600 or 330 => GRole.Motion,
        40 => GRole.Dwell,
        730 or 740 or 760 or 810 or 820 or 830 or 840 or 850 or 860 or 870 or 880 or 890 => GRole.Cycle,
        800 => GRole.CycleCancel,
        270 or 280 or 290 or 300 => GRole.Reference,
        530 => GRole.MachineCoordinates,
        // Data settings (G10, G52, G92.x), macro calls (G65, G66), stored positions (G28.1, G30.1), scaling, mirror and
        // rotation centres (G51, G51.1, G50.1, G68, G68.2), dynamic tool length (G43.1, G43.2), rigid tapping that
        // returns to its start (G33.1).
        100 or 520 or 920 or 921 or 922 or 923 or 650 or 660 or 281 or 301 or 510 or 511 or 501 or 680 or 682 or 431 or 432 or 331 => GRole.AxisData,
        _ => GRole.Mode,
    };

    /// <summary>
    /// True for codes that act only in their own block (the non-modal groups of the format before named groups):
    /// G04, G09, G10, G28, G30, G53, G65, G92; M00, M01, M02, M30, M06, M98, M99.
    /// </summary>
    public static bool ActsOnlyInItsBlock(char letter, int key) => letter == 'M'
        ? key is 0 or 10 or 20 or 300 or 60 or 980 or 990
        : key is 40 or 90 or 100 or 280 or 300 or 530 or 650 or 920;

    /// <summary>
    /// Modal codes whose block takes its axis words as data (scaling G51, mirror G50.1/G51.1, rotation G68/G68.2,
    /// modal macro call G66): written again in a later block, they would turn that block's move into data.
    /// </summary>
    public static bool ReadsAxesWhileInForce(int key) => key is 501 or 510 or 511 or 660 or 680 or 682;

    /// <summary>
    /// True for the words of a mode code that are lengths in program units (converted to millimetres with the rest of
    /// an inch program): G64's path tolerances P and Q (LinuxCNC), G187's corner tolerance E (Haas).
    /// </summary>
    public static bool WordIsLength(int key, char letter) => key switch
    {
        640 => letter is 'P' or 'Q',
        1870 => letter == 'E',
        _ => false,
    };

    /// <summary>True for M codes that end the program (M02, M30).</summary>
    public static bool EndsProgram(int key) => key is 20 or 300;
}
