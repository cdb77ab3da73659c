using System.Globalization;

namespace PmacStream.Machine;

/// <summary>
/// A motor's <c>?</c> status: two 24-bit words, 12 hex digits, most significant first (Turbo SRM pp. 281-284; the bit
/// table is in <c>docs/console.md</c>).
/// </summary>
public readonly record struct MotorWord(int First, int Second)
{
    /// <summary>Parses the reply of <c>#n?</c>; null when it is not 12 hex digits.</summary>
    public static MotorWord? Parse(string reply)
    {
        var text = reply.Trim();
        if (text.Length < 12 ||
            !int.TryParse(text.AsSpan(0, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var first) ||
            !int.TryParse(text.AsSpan(6, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var second))
        {
            return null;
        }

        return new MotorWord(first, second);
    }

    /// <summary>Word 1 bit 23: Motor Activated (Ixx00).</summary>
    public bool Activated => Bit(First, 23);

    /// <summary>Word 1 bit 22: Negative End Limit Set.</summary>
    public bool MinusLimit => Bit(First, 22);

    /// <summary>Word 1 bit 21: Positive End Limit Set.</summary>
    public bool PlusLimit => Bit(First, 21);

    /// <summary>Word 1 bit 19: Amplifier Enabled.</summary>
    public bool AmplifierEnabled => Bit(First, 19);

    /// <summary>Word 1 bit 18: Open Loop Mode (killed).</summary>
    public bool OpenLoop => Bit(First, 18);

    /// <summary>Word 1 bit 17: Move Timer Active (a definite move).</summary>
    public bool MoveTimer => Bit(First, 17);

    /// <summary>Word 1 bit 13: Desired Velocity Zero.</summary>
    public bool VelocityZero => Bit(First, 13);

    /// <summary>Word 1 bit 10: Home Search in Progress.</summary>
    public bool HomeSearch => Bit(First, 10);

    /// <summary>Word 2 bit 11: Stopped on Position Limit.</summary>
    public bool StoppedOnLimit => Bit(Second, 11);

    /// <summary>Word 2 bit 10: Home Complete.</summary>
    public bool HomeComplete => Bit(Second, 10);

    /// <summary>Word 2 bit 3: Amplifier Fault Error.</summary>
    public bool AmplifierFault => Bit(Second, 3);

    /// <summary>Word 2 bit 2: Fatal Following Error.</summary>
    public bool FatalFollowingError => Bit(Second, 2);

    /// <summary>Word 2 bit 1: Warning Following Error.</summary>
    public bool WarningFollowingError => Bit(Second, 1);

    /// <summary>Word 2 bit 0: In Position.</summary>
    public bool InPosition => Bit(Second, 0);

    /// <summary>At rest and in position: no jog, no definite move, no home search.</summary>
    public bool Settled => InPosition && !MoveTimer && !HomeSearch && VelocityZero;

    private static bool Bit(int word, int bit) => ((word >> bit) & 1) == 1;
}

/// <summary>A coordinate system's <c>??</c> status: three 24-bit words (Turbo SRM pp. 284-287).</summary>
public readonly record struct CsWord(int First, int Second, int Third)
{
    /// <summary>Parses the reply of <c>&amp;n??</c>; null when it is not 18 hex digits.</summary>
    public static CsWord? Parse(string reply)
    {
        var text = reply.Trim();
        if (text.Length < 18 ||
            !int.TryParse(text.AsSpan(0, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var a) ||
            !int.TryParse(text.AsSpan(6, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var b) ||
            !int.TryParse(text.AsSpan(12, 6), NumberStyles.HexNumber, CultureInfo.InvariantCulture, out var c))
        {
            return null;
        }

        return new CsWord(a, b, c);
    }

    /// <summary>Word 1 bit 0: Program Running.</summary>
    public bool ProgramRunning => (First & 1) == 1;

    /// <summary>Word 2 bit 20: Amplifier Fault Error (a motor of the C.S.).</summary>
    public bool AmplifierFault => ((Second >> 20) & 1) == 1;

    /// <summary>Word 2 bit 19: Fatal Following Error (a motor of the C.S.).</summary>
    public bool FatalFollowingError => ((Second >> 19) & 1) == 1;

    /// <summary>Word 2 bit 17: In Position (every motor of the C.S.).</summary>
    public bool InPosition => ((Second >> 17) & 1) == 1;
}
