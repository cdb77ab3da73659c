using System.Globalization;

namespace PmacStream.Sim;

/// <summary>What an M-variable points at: itself (<c>*</c>), a bit field of an X:/Y: word, or a whole D:/L:/F: value.</summary>
internal sealed record MDefinition(char Space, int Address, int Bit, int Width, bool Signed)
{
    public static readonly MDefinition Self = new('*', 0, 0, 0, false);

    public bool IsSelf => Space == '*';

    public bool IsBitField => Space is 'X' or 'Y';

    public override string ToString()
    {
        if (IsSelf)
        {
            return "*";
        }

        var address = string.Create(CultureInfo.InvariantCulture, $"{Space}:${Address:X6}");
        if (!IsBitField)
        {
            return address;
        }

        var s = string.Create(CultureInfo.InvariantCulture, $"{address},{Bit}");
        if (Width != 1 || Signed)
        {
            s += string.Create(CultureInfo.InvariantCulture, $",{Width}");
        }

        return Signed ? s + ",S" : s;
    }
}

/// <summary>
/// The controller's variables and the simulated memory words the M-variables point into. Not thread-safe on its own:
/// the simulator's lock guards it.
/// </summary>
internal sealed class SimMemory
{
    public const int Count = 8192;

    public const int CoordinateSystems = 16;

    private readonly double[] _i = new double[Count];
    private readonly double[] _p = new double[Count];
    private readonly double[][] _q;
    private readonly double[] _m = new double[Count];
    private readonly MDefinition[] _mDef = new MDefinition[Count];
    private readonly Dictionary<long, long> _words = [];
    private readonly Dictionary<long, double> _wholeValues = [];

    public SimMemory()
    {
        _q = new double[CoordinateSystems + 1][];
        for (var i = 0; i < _q.Length; i++)
        {
            _q[i] = new double[Count];
        }

        Array.Fill(_mDef, MDefinition.Self);
    }

    public double GetI(int n) => _i[n];

    public void SetI(int n, double v) => _i[n] = v;

    public double GetP(int n) => _p[n];

    public void SetP(int n, double v) => _p[n] = v;

    public double GetQ(int cs, int n) => _q[cs][n];

    public void SetQ(int cs, int n, double v) => _q[cs][n] = v;

    /// <summary>
    /// Registers the firmware computes (a motor's commanded, actual and target position): a D:/L: address it answers,
    /// or null for plain memory.
    /// </summary>
    public Func<char, int, double?>? Register { get; set; }

    public MDefinition GetDefinition(int n) => _mDef[n];

    public void Define(int n, MDefinition def) => _mDef[n] = def;

    public double GetM(int n)
    {
        var d = _mDef[n];
        if (d.IsSelf)
        {
            return _m[n];
        }

        if (!d.IsBitField)
        {
            return Register?.Invoke(d.Space, d.Address) ?? _wholeValues.GetValueOrDefault(Key(d.Space, d.Address));
        }

        var word = GetWord(d.Space, d.Address);
        var mask = d.Width >= 48 ? -1L : (1L << d.Width) - 1;
        var raw = (word >> d.Bit) & mask;
        if (d.Signed && d.Width < 48 && (raw & (1L << (d.Width - 1))) != 0)
        {
            raw -= 1L << d.Width;
        }

        return raw;
    }

    public void SetM(int n, double value)
    {
        var d = _mDef[n];
        if (d.IsSelf)
        {
            _m[n] = value;
            return;
        }

        if (!d.IsBitField)
        {
            _wholeValues[Key(d.Space, d.Address)] = value;
            return;
        }

        var mask = d.Width >= 48 ? -1L : (1L << d.Width) - 1;
        var raw = (long)Math.Round(value) & mask;
        var word = GetWord(d.Space, d.Address);
        word = (word & ~(mask << d.Bit)) | (raw << d.Bit);
        SetWord(d.Space, d.Address, word);
    }

    public long GetWord(char space, int address) => _words.GetValueOrDefault(Key(space, address));

    public void SetWord(char space, int address, long value) => _words[Key(space, address)] = value & 0xFFFFFF;

    /// <summary>Clears variable values (not definitions); used by reset.</summary>
    public void ClearValues()
    {
        Array.Clear(_p);
        Array.Clear(_m);
        foreach (var q in _q)
        {
            Array.Clear(q);
        }
    }

    /// <summary>Factory state: values, definitions and words.</summary>
    public void ClearAll()
    {
        ClearValues();
        Array.Clear(_i);
        Array.Fill(_mDef, MDefinition.Self);
        _words.Clear();
        _wholeValues.Clear();
    }

    private static long Key(char space, int address) => ((long)space << 32) | (uint)address;
}
