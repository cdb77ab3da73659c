using System.Globalization;

namespace PmacStream.Plc;

/// <summary>
/// A ladder file's placement directives: <c>plc N</c>, <c>inputs</c> and <c>outputs</c> (the physical word, the
/// image word, their M-variables and the bits' M-variable base) and <c>internals</c> (the relays' image word and
/// base), each given at most once, with every address and M-variable checked where it is written.
/// </summary>
/// <param name="error">Reports an error (line, column, message).</param>
internal sealed class LadderDirectives(Action<int, int, string> error)
{
    private readonly Dictionary<string, int> _lines = new(StringComparer.OrdinalIgnoreCase);
    private int? _plcLine;

    /// <summary>The PLC program number (<c>plc N</c>), or null.</summary>
    public int? Plc { get; private set; }

    /// <summary>Where the inputs are read.</summary>
    public IoWordConfig Inputs { get; private set; } = IoWordConfig.DefaultInputs;

    /// <summary>Where the outputs are written.</summary>
    public IoWordConfig Outputs { get; private set; } = IoWordConfig.DefaultOutputs;

    /// <summary>Where the internal relays live.</summary>
    public InternalConfig Internals { get; private set; } = InternalConfig.Default;

    /// <summary>The line directive <paramref name="keyword"/> was given on, or <paramref name="fallback"/>.</summary>
    public int LineOf(string keyword, int fallback = 1) => _lines.GetValueOrDefault(keyword, fallback);

    /// <summary>Applies a <c>plc</c>, <c>inputs</c>, <c>outputs</c> or <c>internals</c> line; false for any other keyword (a declaration).</summary>
    public bool Apply(List<LadderWord> words)
    {
        var kw = words[0].Text.ToLowerInvariant();
        switch (kw)
        {
            case "plc":
                if (words.Count != 2 || !int.TryParse(words[1].Text, NumberStyles.None, CultureInfo.InvariantCulture, out var n) || n > 31)
                {
                    Error(words.Count > 1 ? words[1] : words[0], "expected 'plc N' with N a PLC program number 0..31");
                    return true;
                }

                if (_plcLine is { } prev)
                {
                    Error(words[0], $"the PLC number is already set on line {prev}");
                    return true;
                }

                Plc = n;
                _plcLine = words[0].Line;
                return true;
            case "inputs":
            case "outputs":
                if (!Once(words[0]))
                {
                    return true;
                }

                var io = IoDirective(words, kw == "inputs" ? Inputs : Outputs);
                if (kw == "inputs")
                {
                    Inputs = io;
                }
                else
                {
                    Outputs = io;
                }

                return true;
            case "internals":
                if (Once(words[0]))
                {
                    Internals = InternalsDirective(words, Internals);
                }

                return true;
            default:
                return false;
        }
    }

    /// <summary>True the first time a directive is given; a second one is an error.</summary>
    private bool Once(LadderWord keyword)
    {
        if (_lines.TryGetValue(keyword.Text, out var prev))
        {
            Error(keyword, $"'{keyword.Text.ToLowerInvariant()}' is already given on line {prev}");
            return false;
        }

        _lines[keyword.Text] = keyword.Line;
        return true;
    }

    private IoWordConfig IoDirective(List<LadderWord> words, IoWordConfig io)
    {
        foreach (var (key, vw, w) in Clauses(words))
        {
            switch (key)
            {
                case "word":
                    if (ParseAddress(vw, allowX: true, allowBits: true) is { } a)
                    {
                        io = io with { Memory = a.Memory, WordAddress = a.Address, Offset = a.Offset ?? 0, Width = a.Width ?? io.Width };
                    }

                    break;
                case "image":
                    if (ParseAddress(vw, allowX: false, allowBits: false) is { } img)
                    {
                        io = io with { ImageAddress = img.Address };
                    }

                    break;
                case "word-var":
                    if (ParseMVar(vw) is { } wv)
                    {
                        io = io with { WordVariable = wv };
                    }

                    break;
                case "image-var":
                    if (ParseMVar(vw) is { } iv)
                    {
                        io = io with { ImageVariable = iv };
                    }

                    break;
                case "bits":
                    if (ParseMVar(vw) is { } bv)
                    {
                        io = io with { BitBase = bv };
                    }

                    break;
                default:
                    Error(w, $"unknown setting '{key}'; expected word=, image=, word-var=, image-var= or bits=");
                    break;
            }
        }

        return io;
    }

    private InternalConfig InternalsDirective(List<LadderWord> words, InternalConfig cfg)
    {
        foreach (var (key, vw, w) in Clauses(words))
        {
            switch (key)
            {
                case "image":
                    if (ParseAddress(vw, allowX: false, allowBits: false) is { } img)
                    {
                        cfg = cfg with { Address = img.Address };
                    }

                    break;
                case "bits":
                    if (ParseMVar(vw) is { } bv)
                    {
                        cfg = cfg with { BitBase = bv };
                    }

                    break;
                default:
                    Error(w, $"unknown setting '{key}'; expected image= or bits=");
                    break;
            }
        }

        return cfg;
    }

    /// <summary>The KEY=VALUE clauses after the keyword: the key (lower case), the value as a word with its column, the clause; a malformed one is reported and skipped.</summary>
    private IEnumerable<(string Key, LadderWord Value, LadderWord Clause)> Clauses(List<LadderWord> words)
    {
        foreach (var w in words.Skip(1))
        {
            if (SplitClause(w, out var key, out var value, out var valueColumn))
            {
                yield return (key, new LadderWord(value, w.Line, valueColumn), w);
            }
        }
    }

    private bool SplitClause(LadderWord w, out string key, out string value, out int valueColumn)
    {
        var eq = w.Text.IndexOf('=', StringComparison.Ordinal);
        if (eq <= 0 || eq == w.Text.Length - 1)
        {
            Error(w, $"expected KEY=VALUE (no spaces around '='), found '{w.Text}'");
            key = value = "";
            valueColumn = w.Column;
            return false;
        }

        key = w.Text[..eq].ToLowerInvariant();
        value = w.Text[(eq + 1)..];
        valueColumn = w.Column + eq + 1;
        return true;
    }

    private readonly record struct ParsedAddress(char Memory, int Address, int? Offset, int? Width);

    private ParsedAddress? ParseAddress(LadderWord w, bool allowX, bool allowBits)
    {
        var expected = allowBits ? "an address like Y:$078800 or Y:$078800,0,8" : "an address like Y:$0010F0";
        var t = w.Text;
        if (t.Length < 4 || t[1] != ':' || t[2] != '$')
        {
            Error(w, $"expected {expected}, found '{t}'");
            return null;
        }

        var mem = char.ToUpperInvariant(t[0]);
        if (mem != 'Y' && !(allowX && mem == 'X'))
        {
            Error(w, allowX ? $"memory must be X or Y, found '{t[0]}'" : $"image words live in Y memory, found '{t[0]}'");
            return null;
        }

        var parts = t[3..].Split(',');
        if (!int.TryParse(parts[0], NumberStyles.AllowHexSpecifier, CultureInfo.InvariantCulture, out var addr) || addr > 0xFFFFFF)
        {
            Error(w.Line, w.Column + 3, $"expected a hexadecimal address after '$' (at most $FFFFFF), found '{parts[0]}'");
            return null;
        }

        if (!allowBits && parts.Length > 1)
        {
            Error(w, $"expected {expected} (the image width follows the physical word), found '{t}'");
            return null;
        }

        int? offset = null, width = null;
        if (parts.Length > 3)
        {
            Error(w, $"expected {expected}, found '{t}'");
            return null;
        }

        var col = w.Column + 3 + parts[0].Length + 1;
        if (parts.Length > 1)
        {
            if (!int.TryParse(parts[1], NumberStyles.None, CultureInfo.InvariantCulture, out var o) || o > 23)
            {
                Error(w.Line, col, $"expected a bit offset 0..23, found '{parts[1]}'");
                return null;
            }

            offset = o;
            col += parts[1].Length + 1;
        }

        if (parts.Length > 2)
        {
            if (!int.TryParse(parts[2], NumberStyles.None, CultureInfo.InvariantCulture, out var wd) || wd < 1 || wd > 24)
            {
                Error(w.Line, col, $"expected a width 1..24, found '{parts[2]}'");
                return null;
            }

            width = wd;
        }

        if ((offset ?? 0) + (width ?? 1) > 24)
        {
            Error(w, $"offset {offset} + width {width} goes past bit 23 of a 24-bit word");
            return null;
        }

        return new ParsedAddress(mem, addr, offset, width);
    }

    private int? ParseMVar(LadderWord w)
    {
        var t = w.Text;
        if (t.Length < 2 || char.ToUpperInvariant(t[0]) != 'M'
            || !int.TryParse(t.AsSpan(1), NumberStyles.None, CultureInfo.InvariantCulture, out var n) || n > LadderParser.MaxMVariable)
        {
            Error(w, $"expected an M-variable M0..M{LadderParser.MaxMVariable}, found '{t}'");
            return null;
        }

        return n;
    }

    private void Error(int line, int column, string message) => error(line, column, message);

    private void Error(LadderWord w, string message) => error(w.Line, w.Column, message);
}
