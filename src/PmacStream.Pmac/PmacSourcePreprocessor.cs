using System.Text;

namespace PmacStream.Pmac;

/// <summary>One line ready to send, with where it came from.</summary>
internal readonly record struct SourceLine(string Text, string File, int Line);

/// <summary>A <c>#define</c> seen while preparing a download.</summary>
internal sealed record MacroDefinition(string Name, string Value, string File, int Line);

/// <summary>What preparing a PMAC source file produced.</summary>
internal sealed class PreparedSource
{
    public List<SourceLine> Lines { get; } = [];

    public List<MacroDefinition> Macros { get; } = [];

    /// <summary>A host-side problem (missing include, bad directive): ERR number 0, its file and line.</summary>
    public DownloadError? Error { get; set; }
}

/// <summary>
/// PComm's download preparation of a PMAC source file: strips <c>;</c> comments (outside double quotes), drops blank
/// lines, and with <c>macro</c> set runs the small preprocessor PEWIN users rely on: <c>#define NAME value</c>
/// (case-sensitive whole-word substitution, nested up to 16 levels), <c>#undef</c>, <c>#include "file"</c>
/// (relative to the including file), <c>#ifdef/#ifndef/#else/#endif</c>.
/// </summary>
internal static class PmacSourcePreprocessor
{
    private const int MaxIncludeDepth = 16;

    /// <summary>One file being prepared: where it is read from, the name its errors show, and how deep in includes.</summary>
    private sealed record SourceFile(string FullPath, string DisplayPath, bool Macro, Dictionary<string, string> Defines, PreparedSource Result, int Depth);

    /// <summary>One open <c>#ifdef</c>: whether its lines are active, whether the enclosing ones were, and if #else was seen.</summary>
    private readonly record struct Branch(bool Active, bool ParentActive, bool SeenElse);

    public static PreparedSource Prepare(string path, bool macro)
    {
        var result = new PreparedSource();
        var defines = new Dictionary<string, string>(StringComparer.Ordinal);
        var full = Path.GetFullPath(path);
        if (!File.Exists(full))
        {
            result.Error = new DownloadError(0, path, 0, $"file not found: {path}");
            return result;
        }

        Process(new SourceFile(full, path, macro, defines, result, 0));
        return result;
    }

    private static bool Process(SourceFile file)
    {
        // Conditional stack: each entry says whether lines in the current branch are active.
        var active = new Stack<Branch>();
        var lineNo = 0;
        foreach (var rawLine in File.ReadLines(file.FullPath, Encoding.Latin1))
        {
            lineNo++;
            var text = StripComment(rawLine).Trim();
            if (text.Length == 0)
            {
                continue;
            }

            var enabled = active.Count == 0 || active.Peek().Active;
            if (file.Macro && text[0] == '#')
            {
                if (!Directive(file, text, active, enabled, lineNo))
                {
                    return false;
                }

                continue;
            }

            if (!enabled)
            {
                continue;
            }

            if (file.Macro && file.Defines.Count > 0)
            {
                text = Expand(text, file.Defines);
            }

            file.Result.Lines.Add(new SourceLine(text, file.DisplayPath, lineNo));
        }

        if (active.Count > 0)
        {
            return Fail(file.Result, file.DisplayPath, lineNo, "#ifdef without #endif");
        }

        return true;
    }

    /// <summary>
    /// One <c>#</c> line: the conditionals are followed even inside an inactive branch (to find its end); the others
    /// act only in an active one. False when the directive is an error (already recorded).
    /// </summary>
    private static bool Directive(SourceFile file, string text, Stack<Branch> active, bool enabled, int lineNo)
    {
        var (directive, argument) = SplitDirective(text);
        switch (directive)
        {
            case "ifdef":
            case "ifndef":
                {
                    var defined = file.Defines.ContainsKey(FirstWord(argument));
                    active.Push(new Branch(enabled && (directive == "ifdef" ? defined : !defined), enabled, false));
                    return true;
                }

            case "else":
                {
                    if (active.Count == 0 || active.Peek().SeenElse)
                    {
                        return Fail(file.Result, file.DisplayPath, lineNo, "#else without #ifdef");
                    }

                    var top = active.Pop();
                    active.Push(new Branch(top.ParentActive && !top.Active, top.ParentActive, true));
                    return true;
                }

            case "endif":
                if (active.Count == 0)
                {
                    return Fail(file.Result, file.DisplayPath, lineNo, "#endif without #ifdef");
                }

                active.Pop();
                return true;
        }

        if (!enabled)
        {
            return true;
        }

        switch (directive)
        {
            case "define":
                return Define(file, argument, lineNo);
            case "undef":
            case "undefine":
                file.Defines.Remove(FirstWord(argument));
                return true;
            case "include":
                return Include(file, argument, lineNo);
            default:
                return Fail(file.Result, file.DisplayPath, lineNo, $"unknown directive #{directive}");
        }
    }

    private static bool Define(SourceFile file, string argument, int lineNo)
    {
        var name = FirstWord(argument);
        if (name.Length == 0 || !IsIdentifierStart(name[0]))
        {
            return Fail(file.Result, file.DisplayPath, lineNo, "#define needs a name");
        }

        var value = argument[name.Length..].Trim();
        file.Defines[name] = value;
        file.Result.Macros.Add(new MacroDefinition(name, value, file.DisplayPath, lineNo));
        return true;
    }

    /// <summary><c>#include "file"</c>, relative to the including file; prepared in place, with the same defines.</summary>
    private static bool Include(SourceFile file, string argument, int lineNo)
    {
        var name = argument.Trim().Trim('"', '<', '>', '\'');
        if (name.Length == 0)
        {
            return Fail(file.Result, file.DisplayPath, lineNo, "#include needs a file name");
        }

        var includePath = Path.GetFullPath(Path.Combine(Path.GetDirectoryName(file.FullPath)!, name));
        if (!File.Exists(includePath))
        {
            return Fail(file.Result, file.DisplayPath, lineNo, $"#include file not found: {name}");
        }

        if (file.Depth + 1 > MaxIncludeDepth)
        {
            return Fail(file.Result, file.DisplayPath, lineNo, $"#include nested deeper than {MaxIncludeDepth} (a file includes itself?)");
        }

        var includeDisplay = Path.Combine(Path.GetDirectoryName(file.DisplayPath) ?? string.Empty, name);
        return Process(file with { FullPath = includePath, DisplayPath = includeDisplay, Depth = file.Depth + 1 });
    }

    private static bool Fail(PreparedSource result, string file, int line, string message)
    {
        result.Error = new DownloadError(0, file, line, message);
        return false;
    }

    /// <summary>Removes a <c>;</c> comment that is not inside double quotes (CMD"..." and SEND"..." texts).</summary>
    internal static string StripComment(string line)
    {
        var semicolon = line.IndexOf(';');
        if (semicolon < 0)
        {
            return line;
        }

        var quoted = false;
        for (var i = 0; i < line.Length; i++)
        {
            var c = line[i];
            if (c == '"')
            {
                quoted = !quoted;
            }
            else if (c == ';' && !quoted)
            {
                return line[..i];
            }
        }

        return line;
    }

    /// <summary>Replaces whole identifiers that are macro names, repeatedly, outside double quotes.</summary>
    internal static string Expand(string text, Dictionary<string, string> defines)
    {
        for (var pass = 0; pass < 16; pass++)
        {
            var changed = false;
            var sb = new StringBuilder(text.Length + 16);
            var quoted = false;
            var i = 0;
            while (i < text.Length)
            {
                var c = text[i];
                if (c == '"')
                {
                    quoted = !quoted;
                    sb.Append(c);
                    i++;
                    continue;
                }

                if (!quoted && IsIdentifierStart(c) && (i == 0 || !IsIdentifierPart(text[i - 1])))
                {
                    var j = i + 1;
                    while (j < text.Length && IsIdentifierPart(text[j]))
                    {
                        j++;
                    }

                    var word = text[i..j];
                    if (defines.TryGetValue(word, out var value))
                    {
                        sb.Append(value);
                        changed = true;
                    }
                    else
                    {
                        sb.Append(word);
                    }

                    i = j;
                    continue;
                }

                sb.Append(c);
                i++;
            }

            text = sb.ToString();
            if (!changed)
            {
                break;
            }
        }

        return text;
    }

    private static (string Directive, string Argument) SplitDirective(string text)
    {
        var body = text[1..].TrimStart();
        var end = 0;
        while (end < body.Length && char.IsLetter(body[end]))
        {
            end++;
        }

        return (body[..end].ToLowerInvariant(), body[end..].Trim());
    }

    private static string FirstWord(string s)
    {
        var end = 0;
        while (end < s.Length && !char.IsWhiteSpace(s[end]))
        {
            end++;
        }

        return s[..end];
    }

    private static bool IsIdentifierStart(char c) => c is (>= 'A' and <= 'Z') or (>= 'a' and <= 'z') or '_';

    private static bool IsIdentifierPart(char c) => IsIdentifierStart(c) || c is >= '0' and <= '9';
}
