using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// The M codes of a machine profile that stop the program (<see cref="CodeDefinition.Stop"/>), looked up by the code
/// number x 10 as the splitter's word scan reads them: a block with one and no move is tracked as a stop block.
/// </summary>
internal sealed class ProgramStopCodes
{
    private const int Keys = 10_000; // M0 .. M999.9
    private readonly string?[] _codes = new string?[Keys];

    private ProgramStopCodes(MachineProfile profile)
    {
        foreach (var c in profile.MCodes)
        {
            if (c.Stop != ProgramStopKind.None && c.Key is >= 0 and < Keys)
            {
                _codes[c.Key] = c.Code;
            }
        }
    }

    /// <summary>The stop codes of <paramref name="profile"/>.</summary>
    public static ProgramStopCodes Of(MachineProfile profile) => new(profile);

    /// <summary>The profile's spelling of the stop code with this key (<c>M00</c>), or null when it does not stop.</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
    public string? Find(int codeTimesTen) => (uint)codeTimesTen < Keys ? _codes[codeTimesTen] : null;
}
