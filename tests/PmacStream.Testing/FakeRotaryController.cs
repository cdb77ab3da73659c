using System.Globalization;
using System.Text;
using System.Text.RegularExpressions;
using PmacStream.Pmac;

namespace PmacStream.Testing;

/// <summary>One executed move of the fake: its order and the tracking variable at its start.</summary>
public sealed record FakeMove(int Sequence, int SourceLine, double StartSeconds, bool BlockStart = false);

/// <summary>
/// A small, strict Turbo PMAC stand-in for the streaming session's tests (<see cref="FakeRig"/>): a rotary buffer
/// with a word capacity (ERR006 when full), the open/closed rule (anything sent while open is stored, and recorded as
/// a violation when it is an online command), B0/R/S/H/A, M0 and P variables, PR, synchronous M0== written at the
/// start of the move that follows it, % override, and a virtual clock advanced by the test.
/// </summary>
public sealed class FakeRotaryController : IPmacPortEndpoint
{
    private static readonly Regex Motion = new(@"(?<![A-Z])(?:[XYZIJ]\s*[-+]?[\d.]|DWELL)", RegexOptions.IgnoreCase);
    private static readonly Regex Marker = new(@"M0\s*==\s*(\d+)", RegexOptions.IgnoreCase);
    private static readonly Regex Online = new(@"^(?:&\d|M0$|PR$|P\d+$|M0=(?!=)|%|\?\?)", RegexOptions.IgnoreCase);
    private readonly Queue<(string Line, int Words)> _buffer = new();
    private int _words;
    private int? _pending;
    private double _moveLeft;
    private bool _stepping;

    public int CapacityWords { get; set; } = 4000;
    public double MoveSeconds { get; set; } = 0.01;
    public double Override { get; set; } = 100;
    public double Now { get; private set; }
    public bool Open { get; private set; }
    public bool Pointed { get; private set; }
    public bool Running { get; private set; }
    public bool Held { get; private set; }
    public int M0 { get; private set; }
    public Dictionary<int, double> P { get; } = new() { [500] = 1000 };
    public List<FakeMove> Moves { get; } = new();

    /// <summary>Every rotary line executed (motion and non-motion), in order.</summary>
    public List<string> ExecutedLines { get; } = new();
    public List<string> Violations { get; } = new();
    public List<string> Log { get; } = new();
    public int Underruns { get; private set; }
    public bool InMove => _moveLeft > 0;
    public int LinesAhead => _buffer.Count;
    private bool _dry;

    public static int WordsOf(string line) => Math.Max(1, Regex.Matches(line, @"[A-Z]+\s*(?:==|=)?\s*[-+]?[\d.(]", RegexOptions.IgnoreCase).Count);

    public byte[] Execute(string commandLine)
    {
        var cmd = commandLine.Trim();
        var u = cmd.ToUpperInvariant().Replace(" ", string.Empty, StringComparison.Ordinal);
        Log.Add(cmd);
        if (Open)
        {
            if (u == "CLOSE")
            {
                Open = false;
                return Ok();
            }

            if (u is "OPENROT")
            {
                return Ok();
            }

            if (u is "CLEAR")
            {
                _buffer.Clear();
                _words = 0;
                return Ok();
            }

            if (Online.IsMatch(u))
            {
                Violations.Add(cmd);
            }

            var w = WordsOf(cmd);
            if (_words + w > CapacityWords)
            {
                return Err(6);
            }

            _buffer.Enqueue((cmd, w));
            _words += w;
            _dry = false;
            return Ok();
        }

        switch (u)
        {
            case "CLOSE":
                return Ok();
            case "OPENROT":
                Open = true;
                return Ok();
            case "&1B0":
                Pointed = true;
                return Ok();
            case "&1R":
                if (!Pointed)
                {
                    return Err(15);
                }

                Running = true;
                Held = false;
                _stepping = false;
                return Ok();
            case "&1S":
                if (!Pointed)
                {
                    return Err(15);
                }

                Running = true;
                Held = false;
                _stepping = true;
                return Ok();
            case "&1H":
                Held = true;
                return Ok();
            case "&1A":
                Running = false;
                _moveLeft = 0;
                return Ok();
            case "M0":
                return Ok(M0.ToString(CultureInfo.InvariantCulture));
            case "PR":
                return Ok(_buffer.Count.ToString(CultureInfo.InvariantCulture));
            case "&1%":
                return Ok(Override.ToString(CultureInfo.InvariantCulture));
            case "&1??":
                // Second word: bit 17 in position (not moving), bit 21 segments queued (none here: no lookahead).
                return Ok($"{(Running ? 0xA80011 : 0xA80000):X6}{(_moveLeft > 0 ? 0 : 1 << 17):X6}000000");
            case "DELETEGATHER":
                return Ok();
        }

        if (u.StartsWith("&1DEFINEROT", StringComparison.Ordinal))
        {
            CapacityWords = int.Parse(u["&1DEFINEROT".Length..], CultureInfo.InvariantCulture);
            _buffer.Clear();
            _words = 0;
            return Ok();
        }

        if (u.StartsWith("&1DELETEROT", StringComparison.Ordinal))
        {
            return Ok();
        }

        if (u.StartsWith("&1%", StringComparison.Ordinal))
        {
            Override = double.Parse(u[3..], CultureInfo.InvariantCulture);
            return Ok();
        }

        var m = Regex.Match(u, @"^M0=(-?\d+)$");
        if (m.Success)
        {
            M0 = int.Parse(m.Groups[1].Value, CultureInfo.InvariantCulture);
            return Ok();
        }

        m = Regex.Match(u, @"^P(\d+)(?:=(-?[\d.]+))?$");
        if (m.Success)
        {
            var n = int.Parse(m.Groups[1].Value, CultureInfo.InvariantCulture);
            if (m.Groups[2].Success)
            {
                P[n] = double.Parse(m.Groups[2].Value, CultureInfo.InvariantCulture);
                return Ok();
            }

            return Ok(P.GetValueOrDefault(n).ToString(CultureInfo.InvariantCulture));
        }

        return Err(3);
    }

    public void Flush()
    {
    }

    public byte[] Control(char control) => Array.Empty<byte>();

    /// <summary>Runs the virtual clock forward.</summary>
    public void Advance(double seconds)
    {
        var end = Now + seconds;
        while (Now < end - 1e-12)
        {
            if (!Running || Held)
            {
                Now = end;
                return;
            }

            if (_moveLeft > 0)
            {
                var dt = Math.Min(_moveLeft, end - Now);
                _moveLeft -= dt;
                Now += dt;
                if (_moveLeft <= 1e-12 && _stepping)
                {
                    _moveLeft = 0;
                    Held = true;
                }

                continue;
            }

            if (_buffer.Count == 0)
            {
                if (!_dry)
                {
                    _dry = true;
                    Underruns++;
                }

                Now = end;
                return;
            }

            var (line, w) = _buffer.Dequeue();
            _words -= w;
            ExecuteLine(line);
        }
    }

    /// <summary>Underruns that happened before the end of the program (the final dry buffer is not one).</summary>
    public int UnderrunsBefore(bool finished) => finished && _dry ? Underruns - 1 : Underruns;

    private void ExecuteLine(string line)
    {
        var mm = Marker.Match(line);
        var motion = Motion.Match(Marker.Replace(line, " "));
        ExecutedLines.Add(line);
        foreach (Match assign in Regex.Matches(line, @"(?<![A-Z0-9])P(\d+)\s*=\s*(-?[\d.]+)", RegexOptions.IgnoreCase))
        {
            P[int.Parse(assign.Groups[1].Value, CultureInfo.InvariantCulture)] = double.Parse(assign.Groups[2].Value, CultureInfo.InvariantCulture);
        }

        var markerFirst = mm.Success && (!motion.Success || mm.Index < motion.Index);
        if (mm.Success && markerFirst)
        {
            _pending = int.Parse(mm.Groups[1].Value, CultureInfo.InvariantCulture);
        }

        if (motion.Success)
        {
            var blockStart = _pending is not null;
            if (_pending is { } p)
            {
                M0 = p;
                _pending = null;
            }

            Moves.Add(new FakeMove(Moves.Count + 1, M0, Now, blockStart));
            _moveLeft = MoveSeconds * 100.0 / Math.Max(1, Override);
        }

        if (mm.Success && !markerFirst)
        {
            _pending = int.Parse(mm.Groups[1].Value, CultureInfo.InvariantCulture);
        }
    }

    private static byte[] Ok(string? value = null)
    {
        var sb = new StringBuilder();
        if (value is not null)
        {
            sb.Append(value).Append('\r');
        }

        sb.Append('\u0006');
        return Encoding.ASCII.GetBytes(sb.ToString());
    }

    private static byte[] Err(int n) => Encoding.ASCII.GetBytes($"\u0007ERR{n:000}\r");
}
