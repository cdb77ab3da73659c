using System.Globalization;

namespace PmacStream.Plc;

/// <summary>
/// Reads the ladder text format (docs/plc.md): one rung per line, <c>KM1 = !SB1 &amp; (SB2 | KM1) &amp; !KM2 &amp; !KR</c>,
/// plus declarations binding names to input bits, output bits and internal relays, and optional placement
/// directives. Collects every error with its line and column instead of stopping at the first one.
/// </summary>
public static class LadderParser
{
    private static readonly HashSet<string> Keywords = new(StringComparer.OrdinalIgnoreCase)
    {
        "plc", "inputs", "outputs", "internals", "input", "output", "internal",
    };

    /// <summary>Largest M-variable number on a Turbo PMAC.</summary>
    internal const int MaxMVariable = 8191;

    /// <summary>Parses a ladder file's text; throws <see cref="LadderParseException"/> listing every error.</summary>
    /// <param name="text">The whole file.</param>
    /// <param name="file">The name used in error messages.</param>
    public static LadderProgram Parse(string text, string file = "<ladder>")
    {
        var result = TryParse(text, out var diagnostics);
        if (result is null)
        {
            throw new LadderParseException(file, diagnostics);
        }

        return result;
    }

    /// <summary>Parses a ladder file's text; returns null and the errors when it has any.</summary>
    public static LadderProgram? TryParse(string text, out IReadOnlyList<LadderDiagnostic> diagnostics)
    {
        var state = new ParseState();
        state.Run(text);
        diagnostics = state.Diagnostics.OrderBy(d => d.Line).ThenBy(d => d.Column).ToList();
        return diagnostics.Count == 0 ? state.Program : null;
    }

    internal readonly record struct Word(string Text, int Line, int Column);

    internal enum TokKind
    {
        Name,
        Assign,
        And,
        Or,
        Not,
        Open,
        Close,
        End,
    }

    internal readonly record struct Token(TokKind Kind, string Text, int Line, int Column);

    private sealed record PendingDecl(LadderSymbolKind Kind, Word Name, Word? Bit, string? Comment);

    private sealed record PendingRung(Word Coil, List<Token> Tokens, int Line);

    private sealed class ParseState
    {
        public List<LadderDiagnostic> Diagnostics { get; } = [];

        public LadderProgram? Program { get; private set; }

        private int? _plc;
        private int? _plcLine;
        private IoWordConfig _inputs = IoWordConfig.DefaultInputs;
        private IoWordConfig _outputs = IoWordConfig.DefaultOutputs;
        private InternalConfig _internals = InternalConfig.Default;
        private readonly Dictionary<string, int> _directiveLines = new(StringComparer.OrdinalIgnoreCase);
        private readonly List<PendingDecl> _decls = [];
        private readonly List<PendingRung> _rungs = [];

        private void Error(int line, int column, string message) => Diagnostics.Add(new LadderDiagnostic(line, column, message));

        private void Error(Word w, string message) => Error(w.Line, w.Column, message);

        public void Run(string text)
        {
            var lines = text.Replace("\r\n", "\n", StringComparison.Ordinal).Replace('\r', '\n').Split('\n');
            PendingRung? open = null;
            PendingRung? previousRung = null;
            for (var i = 0; i < lines.Length; i++)
            {
                var lineNo = i + 1;
                var raw = lines[i];
                var (code, comment) = SplitComment(raw);
                if (code.Trim().Length == 0)
                {
                    continue;
                }

                if (open is not null)
                {
                    // A rung continues while a bracket is open or the previous line ended with an operator, unless
                    // the line plainly starts a new rung (a forgotten ')' is then reported on the unfinished rung).
                    var more = new List<Token>();
                    Tokenize(code, lineNo, more);
                    var startsRung = more.Count >= 2 && more[0].Kind == TokKind.Name && more[1].Kind == TokKind.Assign;
                    if (!startsRung)
                    {
                        open.Tokens.AddRange(more);
                        previousRung = open;
                        if (!NeedsContinuation(open.Tokens))
                        {
                            open = null;
                        }

                        continue;
                    }

                    open = null;
                }

                var trimmed = code.TrimStart();
                if (previousRung is not null && (trimmed[0] == '&' || trimmed[0] == '|'))
                {
                    // A line that starts with an operator carries on the rung just above it.
                    Tokenize(code, lineNo, previousRung.Tokens);
                    if (NeedsContinuation(previousRung.Tokens))
                    {
                        open = previousRung;
                    }

                    continue;
                }

                previousRung = null;
                var words = SplitWords(code, lineNo);
                var first = words[0];
                var isRung = words.Count >= 2 && words[1].Text.StartsWith('=') || first.Text.Contains('=', StringComparison.Ordinal);
                if (!isRung && Keywords.Contains(first.Text))
                {
                    Directive(words, comment);
                    continue;
                }

                var tokens = new List<Token>();
                Tokenize(code, lineNo, tokens);
                if (tokens.Count < 2 || tokens[0].Kind != TokKind.Name || tokens[1].Kind != TokKind.Assign)
                {
                    Error(first, $"expected a rung 'COIL = contacts' or a declaration (input, output, internal, plc, inputs, outputs, internals), found '{first.Text}'");
                    continue;
                }

                var rung = new PendingRung(new Word(tokens[0].Text, tokens[0].Line, tokens[0].Column), tokens.Skip(2).ToList(), lineNo);
                _rungs.Add(rung);
                previousRung = rung;
                if (NeedsContinuation(rung.Tokens))
                {
                    open = rung;
                }
            }

            if (open is not null)
            {
                var last = open.Tokens.Count > 0 ? open.Tokens[^1] : new Token(TokKind.End, "", open.Coil.Line, open.Coil.Column);
                Error(last.Line, last.Column, "the rung is not finished at the end of the file (an open '(' or a trailing operator)");
                _rungs.Remove(open);
            }

            Build();
        }

        private static bool NeedsContinuation(List<Token> tokens)
        {
            if (tokens.Count == 0)
            {
                return true;
            }

            var depth = 0;
            foreach (var t in tokens)
            {
                depth += t.Kind == TokKind.Open ? 1 : t.Kind == TokKind.Close ? -1 : 0;
            }

            var last = tokens[^1].Kind;
            return depth > 0 || last is TokKind.And or TokKind.Or or TokKind.Not or TokKind.Open;
        }

        private static (string Code, string? Comment) SplitComment(string raw)
        {
            var cut = raw.IndexOfAny(['#', ';']);
            if (cut < 0)
            {
                return (raw, null);
            }

            var comment = raw[(cut + 1)..].Trim();
            return (raw[..cut], comment.Length == 0 ? null : comment);
        }

        private static List<Word> SplitWords(string code, int line)
        {
            var words = new List<Word>();
            var i = 0;
            while (i < code.Length)
            {
                if (char.IsWhiteSpace(code[i]))
                {
                    i++;
                    continue;
                }

                var start = i;
                while (i < code.Length && !char.IsWhiteSpace(code[i]))
                {
                    i++;
                }

                words.Add(new Word(code[start..i], line, start + 1));
            }

            return words;
        }

        private void Tokenize(string code, int line, List<Token> into)
        {
            var i = 0;
            while (i < code.Length)
            {
                var c = code[i];
                if (char.IsWhiteSpace(c))
                {
                    i++;
                    continue;
                }

                var col = i + 1;
                TokKind? single = c switch
                {
                    '=' => TokKind.Assign,
                    '&' => TokKind.And,
                    '|' => TokKind.Or,
                    '!' => TokKind.Not,
                    '(' => TokKind.Open,
                    ')' => TokKind.Close,
                    _ => null,
                };
                if (single is { } k)
                {
                    into.Add(new Token(k, c.ToString(), line, col));
                    i++;
                    continue;
                }

                if (char.IsLetter(c) || c == '_')
                {
                    var start = i;
                    while (i < code.Length && (char.IsLetterOrDigit(code[i]) || code[i] == '_'))
                    {
                        i++;
                    }

                    into.Add(new Token(TokKind.Name, code[start..i], line, col));
                    continue;
                }

                var hint = c switch
                {
                    '^' => " (write a normally-closed contact as !NAME; the generator emits the ^1 form)",
                    '~' or '/' => " (write a normally-closed contact as !NAME)",
                    '+' => " (write parallel branches with |)",
                    '*' => " (write contacts in series with &)",
                    _ => "",
                };
                Error(line, col, $"unexpected character '{c}'; expected a name, '&', '|', '!', '(' or ')'{hint}");
                i++;
            }
        }

        private void Directive(List<Word> words, string? comment)
        {
            var kw = words[0].Text.ToLowerInvariant();
            switch (kw)
            {
                case "plc":
                    if (words.Count != 2 || !int.TryParse(words[1].Text, NumberStyles.None, CultureInfo.InvariantCulture, out var n) || n > 31)
                    {
                        Error(words.Count > 1 ? words[1] : words[0], "expected 'plc N' with N a PLC program number 0..31");
                        return;
                    }

                    if (_plcLine is { } prev)
                    {
                        Error(words[0], $"the PLC number is already set on line {prev}");
                        return;
                    }

                    _plc = n;
                    _plcLine = words[0].Line;
                    return;
                case "inputs":
                case "outputs":
                    if (!Once(words[0]))
                    {
                        return;
                    }

                    var io = kw == "inputs" ? _inputs : _outputs;
                    io = IoDirective(words, io);
                    if (kw == "inputs")
                    {
                        _inputs = io;
                    }
                    else
                    {
                        _outputs = io;
                    }

                    return;
                case "internals":
                    if (Once(words[0]))
                    {
                        _internals = InternalsDirective(words, _internals);
                    }

                    return;
                default:
                    Declaration(kw, words, comment);
                    return;
            }
        }

        private bool Once(Word keyword)
        {
            if (_directiveLines.TryGetValue(keyword.Text, out var prev))
            {
                Error(keyword, $"'{keyword.Text.ToLowerInvariant()}' is already given on line {prev}");
                return false;
            }

            _directiveLines[keyword.Text] = keyword.Line;
            return true;
        }

        private IoWordConfig IoDirective(List<Word> words, IoWordConfig io)
        {
            foreach (var w in words.Skip(1))
            {
                if (!SplitClause(w, out var key, out var value, out var valueCol))
                {
                    continue;
                }

                var vw = new Word(value, w.Line, valueCol);
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

        private InternalConfig InternalsDirective(List<Word> words, InternalConfig cfg)
        {
            foreach (var w in words.Skip(1))
            {
                if (!SplitClause(w, out var key, out var value, out var valueCol))
                {
                    continue;
                }

                var vw = new Word(value, w.Line, valueCol);
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

        private bool SplitClause(Word w, out string key, out string value, out int valueColumn)
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

        private ParsedAddress? ParseAddress(Word w, bool allowX, bool allowBits)
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

        private int? ParseMVar(Word w)
        {
            var t = w.Text;
            if (t.Length < 2 || char.ToUpperInvariant(t[0]) != 'M'
                || !int.TryParse(t.AsSpan(1), NumberStyles.None, CultureInfo.InvariantCulture, out var n) || n > MaxMVariable)
            {
                Error(w, $"expected an M-variable M0..M{MaxMVariable}, found '{t}'");
                return null;
            }

            return n;
        }

        private void Declaration(string kw, List<Word> words, string? comment)
        {
            var kind = kw switch
            {
                "input" => LadderSymbolKind.Input,
                "output" => LadderSymbolKind.Output,
                _ => LadderSymbolKind.Internal,
            };
            var expectedShape = kind == LadderSymbolKind.Internal ? "'internal NAME'" : $"'{kw} NAME BIT'";
            var wanted = kind == LadderSymbolKind.Internal ? 2 : 3;
            if (words.Count != wanted)
            {
                var at = words.Count > wanted ? words[wanted] : words[^1];
                Error(at, $"expected {expectedShape}{(kind == LadderSymbolKind.Internal ? "" : " with BIT the bit number in the word")}");
                return;
            }

            var name = words[1];
            if (!IsName(name.Text))
            {
                Error(name, $"'{name.Text}' is not a valid name (letters, digits and _, starting with a letter or _)");
                return;
            }

            if (Keywords.Contains(name.Text))
            {
                Error(name, $"'{name.Text}' is a keyword and cannot be used as a name");
                return;
            }

            Word? bit = kind == LadderSymbolKind.Internal ? null : words[2];
            _decls.Add(new PendingDecl(kind, name, bit, comment));
        }

        private static bool IsName(string s) =>
            s.Length > 0 && (char.IsLetter(s[0]) || s[0] == '_') && s.All(c => char.IsLetterOrDigit(c) || c == '_');

        private void Build()
        {
            ValidateIo("inputs", _inputs);
            ValidateIo("outputs", _outputs);
            var symbols = new List<LadderSymbol>();
            var byName = new Dictionary<string, LadderSymbol>(StringComparer.OrdinalIgnoreCase);
            var bitsTaken = new Dictionary<(LadderSymbolKind, int), LadderSymbol>();
            var internalIndex = 0;
            foreach (var d in _decls)
            {
                if (byName.TryGetValue(d.Name.Text, out var prior))
                {
                    Error(d.Name, $"'{d.Name.Text}' is already declared on line {prior.Line}");
                    continue;
                }

                int bit;
                int mvar;
                if (d.Kind == LadderSymbolKind.Internal)
                {
                    bit = internalIndex++;
                    mvar = _internals.BitBase + bit;
                }
                else
                {
                    var io = d.Kind == LadderSymbolKind.Input ? _inputs : _outputs;
                    var bw = d.Bit!.Value;
                    if (!int.TryParse(bw.Text, NumberStyles.None, CultureInfo.InvariantCulture, out bit) || bit >= io.Width)
                    {
                        Error(bw, $"expected a bit number 0..{io.Width - 1} (the {(d.Kind == LadderSymbolKind.Input ? "inputs" : "outputs")} word is {io.Width} bits wide), found '{bw.Text}'");
                        continue;
                    }

                    if (bitsTaken.TryGetValue((d.Kind, bit), out var other))
                    {
                        Error(bw, $"{d.Kind.ToString().ToLowerInvariant()} bit {bit} is already '{other.Name}' (line {other.Line})");
                        continue;
                    }

                    mvar = io.BitBase + bit;
                }

                var sym = new LadderSymbol(d.Name.Text, d.Kind, bit, mvar, d.Comment, d.Name.Line);
                if (d.Kind != LadderSymbolKind.Internal)
                {
                    bitsTaken[(d.Kind, bit)] = sym;
                }

                if (mvar > MaxMVariable)
                {
                    Error(d.Name, $"'{d.Name.Text}' would be M{mvar}, past M{MaxMVariable}; lower the bits= base");
                    continue;
                }

                byName[d.Name.Text] = sym;
                symbols.Add(sym);
            }

            CheckVariableClashes(symbols);
            CheckAddressClashes(internalIndex);

            var rungs = new List<LadderRung>();
            var driven = new Dictionary<LadderSymbol, int>();
            foreach (var r in _rungs)
            {
                LadderSymbol? coil = null;
                if (!byName.TryGetValue(r.Coil.Text, out var c))
                {
                    Error(r.Coil, $"coil '{r.Coil.Text}' is not declared; declare it with 'output {r.Coil.Text} BIT' or 'internal {r.Coil.Text}'");
                }
                else if (c.Kind == LadderSymbolKind.Input)
                {
                    Error(r.Coil, $"'{c.Name}' is an input (line {c.Line}); a rung can only drive an output or an internal relay");
                }
                else if (driven.TryGetValue(c, out var first))
                {
                    Error(r.Coil, $"coil '{c.Name}' is already driven by the rung on line {first} (double coil); combine the two rungs with |");
                }
                else
                {
                    coil = c;
                    driven[c] = r.Line;
                }

                var parser = new ExprParser(r.Tokens, byName, this, r.Line);
                var network = parser.ParseRung();
                if (coil is not null && network is not null)
                {
                    rungs.Add(new LadderRung(coil, network, r.Line));
                }
            }

            if (_rungs.Count == 0 && Diagnostics.Count == 0)
            {
                Error(1, 1, "the file has no rungs; write at least one 'COIL = contacts' line");
            }

            Program = new LadderProgram(_plc, _inputs, _outputs, _internals, symbols, rungs);
        }

        private void ValidateIo(string kw, IoWordConfig io)
        {
            if (io.Offset + io.Width > 24)
            {
                var line = _directiveLines.GetValueOrDefault(kw, 1);
                Error(line, 1, $"{kw}: offset {io.Offset} + width {io.Width} goes past bit 23 of a 24-bit word");
            }
        }

        private void CheckVariableClashes(List<LadderSymbol> symbols)
        {
            var owners = new Dictionary<int, string>();
            void Claim(int m, string what, int line)
            {
                if (owners.TryGetValue(m, out var other))
                {
                    Error(line, 1, $"M{m} would be used twice: for {other} and for {what}; move a bits=/word-var=/image-var= base");
                }
                else
                {
                    owners[m] = what;
                }
            }

            Claim(_inputs.WordVariable, "the physical inputs word", _directiveLines.GetValueOrDefault("inputs", 1));
            Claim(_inputs.ImageVariable, "the input image", _directiveLines.GetValueOrDefault("inputs", 1));
            Claim(_outputs.WordVariable, "the physical outputs word", _directiveLines.GetValueOrDefault("outputs", 1));
            Claim(_outputs.ImageVariable, "the output image", _directiveLines.GetValueOrDefault("outputs", 1));
            foreach (var s in symbols)
            {
                Claim(s.MVariable, $"'{s.Name}'", s.Line);
            }
        }

        private void CheckAddressClashes(int internalCount)
        {
            var internalWords = (internalCount + 23) / 24;
            var images = new[] { (_inputs.ImageAddress, "inputs"), (_outputs.ImageAddress, "outputs") };
            if (_inputs.ImageAddress == _outputs.ImageAddress)
            {
                Error(_directiveLines.GetValueOrDefault("outputs", 1), 1, $"the input and output images are both at Y:${_inputs.ImageAddress:X6}; give them different image= words");
            }

            foreach (var (addr, kw) in images)
            {
                if (internalWords > 0 && addr >= _internals.Address && addr < _internals.Address + internalWords)
                {
                    Error(_directiveLines.GetValueOrDefault("internals", _directiveLines.GetValueOrDefault(kw, 1)), 1,
                        $"the internal relays (Y:${_internals.Address:X6}, {internalWords} word(s)) overlap the {kw} image at Y:${addr:X6}");
                }
            }
        }

        /// <summary>Recursive descent over one rung's tokens: | is lowest, then &amp;, then ! and brackets.</summary>
        private sealed class ExprParser(List<Token> tokens, Dictionary<string, LadderSymbol> names, ParseState state, int line)
        {
            private int _pos;
            private bool _failed;

            private Token Peek => _pos < tokens.Count ? tokens[_pos] : EndToken;

            private Token EndToken => tokens.Count > 0
                ? new Token(TokKind.End, "", tokens[^1].Line, tokens[^1].Column + tokens[^1].Text.Length)
                : new Token(TokKind.End, "", line, 1);

            public LadderExpr? ParseRung()
            {
                var e = Parallel();
                if (!_failed && Peek.Kind != TokKind.End)
                {
                    var t = Peek;
                    Fail(t, t.Kind == TokKind.Close
                        ? "unmatched ')'"
                        : $"expected '&', '|' or the end of the rung, found {Describe(t)}");
                }

                return _failed ? null : e;
            }

            private void Fail(Token t, string message)
            {
                if (!_failed)
                {
                    state.Error(t.Line, t.Column, message);
                }

                _failed = true;
            }

            private static string Describe(Token t) => t.Kind == TokKind.End ? "the end of the rung" : $"'{t.Text}'";

            private LadderExpr? Parallel()
            {
                var first = Series();
                if (first is null)
                {
                    return null;
                }

                List<LadderExpr>? items = null;
                while (!_failed && Peek.Kind == TokKind.Or)
                {
                    _pos++;
                    var next = Series();
                    if (next is null)
                    {
                        return null;
                    }

                    items ??= [.. Splice<LadderParallel>(first)];
                    items.AddRange(Splice<LadderParallel>(next));
                }

                return items is null ? first : new LadderParallel(items);
            }

            private LadderExpr? Series()
            {
                var first = Factor();
                if (first is null)
                {
                    return null;
                }

                List<LadderExpr>? items = null;
                while (!_failed && Peek.Kind == TokKind.And)
                {
                    _pos++;
                    var next = Factor();
                    if (next is null)
                    {
                        return null;
                    }

                    items ??= [.. Splice<LadderSeries>(first)];
                    items.AddRange(Splice<LadderSeries>(next));
                }

                return items is null ? first : new LadderSeries(items);
            }

            private static IEnumerable<LadderExpr> Splice<T>(LadderExpr e)
                where T : LadderExpr => e switch
                {
                    LadderSeries s when typeof(T) == typeof(LadderSeries) => s.Items,
                    LadderParallel p when typeof(T) == typeof(LadderParallel) => p.Items,
                    _ => [e],
                };

            private LadderExpr? Factor()
            {
                var t = Peek;
                switch (t.Kind)
                {
                    case TokKind.Not:
                        _pos++;
                        var inner = Factor();
                        return inner switch
                        {
                            null => null,
                            LadderContact c => c with { NormallyClosed = !c.NormallyClosed },
                            LadderNot n => n.Inner,
                            _ => new LadderNot(inner),
                        };
                    case TokKind.Open:
                        _pos++;
                        var group = Parallel();
                        if (group is null)
                        {
                            return null;
                        }

                        if (Peek.Kind != TokKind.Close)
                        {
                            Fail(Peek, $"expected ')' to close the '(' at column {t.Column}{(t.Line != Peek.Line ? $" of line {t.Line}" : "")}, found {Describe(Peek)}");
                            return null;
                        }

                        _pos++;
                        return group;
                    case TokKind.Name:
                        _pos++;
                        if (!names.TryGetValue(t.Text, out var sym))
                        {
                            Fail(t, $"'{t.Text}' is not declared; declare it with input, output or internal");
                            return null;
                        }

                        return new LadderContact(sym, false);
                    default:
                        Fail(t, $"expected a contact name, '!' or '(', found {Describe(t)}");
                        return null;
                }
            }
        }
    }
}
