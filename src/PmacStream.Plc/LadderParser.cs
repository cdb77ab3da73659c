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

    private sealed record PendingDecl(LadderSymbolKind Kind, LadderWord Name, LadderWord? Bit, string? Comment);

    private sealed record PendingRung(LadderWord Coil, List<LadderToken> Tokens, int Line);

    private sealed class ParseState
    {
        public List<LadderDiagnostic> Diagnostics { get; } = [];

        public LadderProgram? Program { get; private set; }

        private readonly List<PendingDecl> _decls = [];
        private readonly List<PendingRung> _rungs = [];
        private readonly LadderDirectives _directives;

        public ParseState() => _directives = new LadderDirectives(Error);

        private IoWordConfig Inputs => _directives.Inputs;

        private IoWordConfig Outputs => _directives.Outputs;

        private InternalConfig Internals => _directives.Internals;

        private void Error(int line, int column, string message) => Diagnostics.Add(new LadderDiagnostic(line, column, message));

        private void Error(LadderWord w, string message) => Error(w.Line, w.Column, message);

        public void Run(string text)
        {
            var lines = text.Replace("\r\n", "\n", StringComparison.Ordinal).Replace('\r', '\n').Split('\n');
            PendingRung? open = null;
            PendingRung? previousRung = null;
            for (var i = 0; i < lines.Length; i++)
            {
                var lineNo = i + 1;
                var raw = lines[i];
                var (code, comment) = LadderLexer.SplitComment(raw);
                if (code.Trim().Length == 0)
                {
                    continue;
                }

                if (open is not null)
                {
                    // A rung continues while a bracket is open or the previous line ended with an operator, unless
                    // the line plainly starts a new rung (a forgotten ')' is then reported on the unfinished rung).
                    var more = new List<LadderToken>();
                    LadderLexer.Tokenize(code, lineNo, more, Error);
                    var startsRung = more.Count >= 2 && more[0].Kind == LadderTokenKind.Name && more[1].Kind == LadderTokenKind.Assign;
                    if (!startsRung)
                    {
                        open.Tokens.AddRange(more);
                        previousRung = open;
                        if (!LadderLexer.NeedsContinuation(open.Tokens))
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
                    LadderLexer.Tokenize(code, lineNo, previousRung.Tokens, Error);
                    if (LadderLexer.NeedsContinuation(previousRung.Tokens))
                    {
                        open = previousRung;
                    }

                    continue;
                }

                previousRung = Statement(code, lineNo, comment);
                if (previousRung is not null && LadderLexer.NeedsContinuation(previousRung.Tokens))
                {
                    open = previousRung;
                }
            }

            if (open is not null)
            {
                var last = open.Tokens.Count > 0 ? open.Tokens[^1] : new LadderToken(LadderTokenKind.End, "", open.Coil.Line, open.Coil.Column);
                Error(last.Line, last.Column, "the rung is not finished at the end of the file (an open '(' or a trailing operator)");
                _rungs.Remove(open);
            }

            Build();
        }

        /// <summary>A line that starts something: a directive, a declaration, or a rung (returned; null otherwise).</summary>
        private PendingRung? Statement(string code, int lineNo, string? comment)
        {
            var words = LadderLexer.SplitWords(code, lineNo);
            var first = words[0];
            var isRung = words.Count >= 2 && words[1].Text.StartsWith('=') || first.Text.Contains('=', StringComparison.Ordinal);
            if (!isRung && Keywords.Contains(first.Text))
            {
                if (!_directives.Apply(words))
                {
                    Declaration(first.Text.ToLowerInvariant(), words, comment);
                }

                return null;
            }

            var tokens = new List<LadderToken>();
            LadderLexer.Tokenize(code, lineNo, tokens, Error);
            if (tokens.Count < 2 || tokens[0].Kind != LadderTokenKind.Name || tokens[1].Kind != LadderTokenKind.Assign)
            {
                Error(first, $"expected a rung 'COIL = contacts' or a declaration (input, output, internal, plc, inputs, outputs, internals), found '{first.Text}'");
                return null;
            }

            var rung = new PendingRung(new LadderWord(tokens[0].Text, tokens[0].Line, tokens[0].Column), tokens.Skip(2).ToList(), lineNo);
            _rungs.Add(rung);
            return rung;
        }

        private void Declaration(string kw, List<LadderWord> words, string? comment)
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

            LadderWord? bit = kind == LadderSymbolKind.Internal ? null : words[2];
            _decls.Add(new PendingDecl(kind, name, bit, comment));
        }

        private static bool IsName(string s) =>
            s.Length > 0 && (char.IsLetter(s[0]) || s[0] == '_') && s.All(c => char.IsLetterOrDigit(c) || c == '_');

        private void Build()
        {
            ValidateIo("inputs", Inputs);
            ValidateIo("outputs", Outputs);
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
                    mvar = Internals.BitBase + bit;
                }
                else
                {
                    var io = d.Kind == LadderSymbolKind.Input ? Inputs : Outputs;
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
            var rungs = Rungs(byName);
            if (_rungs.Count == 0 && Diagnostics.Count == 0)
            {
                Error(1, 1, "the file has no rungs; write at least one 'COIL = contacts' line");
            }

            Program = new LadderProgram(_directives.Plc, Inputs, Outputs, Internals, symbols, rungs);
        }

        /// <summary>The rungs whose coil may be driven (declared, not an input, not driven twice) and which parse.</summary>
        private List<LadderRung> Rungs(Dictionary<string, LadderSymbol> byName)
        {
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

                var parser = new RungParser(r.Tokens, byName, Error, r.Line);
                var network = parser.ParseRung();
                if (coil is not null && network is not null)
                {
                    rungs.Add(new LadderRung(coil, network, r.Line));
                }
            }

            return rungs;
        }

        private void ValidateIo(string kw, IoWordConfig io)
        {
            if (io.Offset + io.Width > 24)
            {
                var line = _directives.LineOf(kw);
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

            Claim(Inputs.WordVariable, "the physical inputs word", _directives.LineOf("inputs"));
            Claim(Inputs.ImageVariable, "the input image", _directives.LineOf("inputs"));
            Claim(Outputs.WordVariable, "the physical outputs word", _directives.LineOf("outputs"));
            Claim(Outputs.ImageVariable, "the output image", _directives.LineOf("outputs"));
            foreach (var s in symbols)
            {
                Claim(s.MVariable, $"'{s.Name}'", s.Line);
            }
        }

        private void CheckAddressClashes(int internalCount)
        {
            var internalWords = (internalCount + 23) / 24;
            var images = new[] { (Inputs.ImageAddress, "inputs"), (Outputs.ImageAddress, "outputs") };
            if (Inputs.ImageAddress == Outputs.ImageAddress)
            {
                Error(_directives.LineOf("outputs"), 1, $"the input and output images are both at Y:${Inputs.ImageAddress:X6}; give them different image= words");
            }

            foreach (var (addr, kw) in images)
            {
                if (internalWords > 0 && addr >= Internals.Address && addr < Internals.Address + internalWords)
                {
                    Error(_directives.LineOf("internals", _directives.LineOf(kw)), 1,
                        $"the internal relays (Y:${Internals.Address:X6}, {internalWords} word(s)) overlap the {kw} image at Y:${addr:X6}");
                }
            }
        }
    }
}
