namespace PmacStream.GCode;

/// <summary>
/// Which program families (CAM posts, senders, hand-written shop programs) fit which built-in profile, and the
/// dialect hazards the check warns about (W009-W014): the section of docs/profiles.md that says so.
/// </summary>
public static class ProgramFamilies
{
    /// <summary>The markdown section, as docs/profiles.md has it.</summary>
    public const string Markdown = """
        ## Which programs fit which profile

        A program means what its author's controller makes of it. Where FANUC/Haas, LinuxCNC and grbl read one code
        differently, a program checked under the other dialect's profile runs with a meaning its author did not intend,
        so pick the profile by where the program comes from:

        | program family | examples (`../shared/gcode-corpus`) | profile |
        |---|---|---|
        | FANUC and Haas posts: Fusion 360/HSM "FANUC" and "Haas", Mastercam, FreeCAD's FANUC post, Vectric's FANUC post; hand-written Haas and FANUC shop programs | router_panel.ngc, fusion-inch.nc, smiley.nc, mill_hp_2.nc | `fanuc-mill` |
        | LinuxCNC: Fusion's Tormach and LinuxCNC posts, FreeCAD's LinuxCNC post, CAMotics and OpenVoronoi output, Estlcam's LinuxCNC post, anything with o-words or `#` parameters | 1003.nc (Tormach), vcarve.ngc, Enclosure.nc | `linuxcnc-mill` |
        | grbl senders and their posts: gSender, UGS, Candle, bCNC, Easel, Carbide Create, Vectric's "Grbl" posts, Estlcam's grbl post, Inkscape gcodetools | MB-2.3_test.nc, KB-22_test.gcode, Nikola.nc, flower_mold.nc | `grbl` (or `linuxcnc-mill`, which reads the same codes the same way and has more of them) |
        | the checking paper's set | | `paper-24g7m` |

        The codes that mean different things, and what the check says when a program uses one the other dialect's way
        (a warning: the block runs with the profile's meaning; the warning names both):

        | code | FANUC / Haas (`fanuc-mill`) | LinuxCNC (`linuxcnc-mill`), grbl (`grbl`) | warning |
        |---|---|---|---|
        | `G10 L20 P1 X0 Y0 Z50` | sets the extended work offset `G54.1 P1` to the values | sets `G54` so that the current position reads X0 Y0 Z50 (gSender's "zero here") | W009 under `fanuc-mill` when a move follows in `G54`-`G59` and the program selects no `G54.1 P`: the moves run off by the offset the program meant to set |
        | `G04 P` | milliseconds (no decimal point) | seconds | W010 for a fraction under a millisecond profile, or 100 and more under a seconds profile |
        | `G10 L2 P0` | the external work offset, added to every work coordinate system | the work offset in force | W011 always: both meanings are common |
        | `G28`/`G30` without axis words | FANUC: moves no axis; Haas: every axis to machine zero | every axis to the stored position | W012 (this host moves none under every profile); smiley.nc and mill_hp_2.nc (Haas, "G28 (Machine Home)") and 1003.nc (Tormach, `G30`) mean every axis |
        | `G90 G28 Z0` | through work Z0 (the intermediate point), then home | the same | W012 when the intermediate move moves: posts write `G91 G28 Z0` to go straight home |
        | `M06` with no `T` since the last change | changes to the last `T` (preselected) | the same | W013: a program for a control that takes the `T` after `M06` means a later block's `T` |
        | `G92` left in force at program end | cleared by reset | kept for the next program and across restarts until `G92.1` | W014: this host starts every job without it |

        Also by dialect, refused rather than warned: `G54.1`, `M98`/`M99`, `G65` are FANUC's (E104 under the others);
        o-words and `#` parameters are LinuxCNC's (E102 under every profile until the expander runs them); `M6` is not
        grbl's (E105); the arc tolerance differs (`arcTolerance`, below: LinuxCNC's rule for `fanuc-mill` and
        `linuxcnc-mill`, grbl's own for `grbl`).


        """;
}
