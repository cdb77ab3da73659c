using System.Globalization;

namespace PmacStream.GCode;

/// <summary>
/// Diagnostic message texts by code and culture. English is built in; Simplified Chinese comes from the same table
/// so that a missing translation falls back to English instead of failing.
/// </summary>
public static class DiagnosticText
{
    private static readonly Dictionary<string, (string En, string Zh)> Texts = new()
    {
        [DiagnosticCodes.IllegalCharacter] = ("illegal character '{0}': expected an address letter A-Z, '(' or ';'", "非法字符 '{0}'：应为地址字母 A-Z、'(' 或 ';'"),
        [DiagnosticCodes.MalformedNumber] = ("malformed number after '{0}': expected digits such as 1, -2.5 or .5", "'{0}' 后的数值格式错误：应为数字，如 1、-2.5 或 .5"),
        [DiagnosticCodes.UnclosedComment] = ("unclosed comment: expected ')' before the end of the line", "注释未闭合：行尾之前应有 ')'"),
        [DiagnosticCodes.LineTooLong] = ("line longer than {0} bytes: the rest of the line is ignored", "行长度超过 {0} 字节：其余部分被忽略"),
        [DiagnosticCodes.LowercaseLetter] = ("lowercase letter '{0}': accepted, but write address letters in upper case", "小写字母 '{0}'：可以接受，但地址字母应大写"),
    };

    /// <summary>The culture messages are written in; defaults to the current UI culture.</summary>
    public static CultureInfo Culture { get; set; } = CultureInfo.CurrentUICulture;

    /// <summary>Registers or replaces a message (the checker adds its codes here).</summary>
    public static void Register(string code, string english, string chinese) => Texts[code] = (english, chinese);

    /// <summary>Formats the message for a code in <see cref="Culture"/>.</summary>
    public static string Format(string code, params object[] args)
    {
        if (!Texts.TryGetValue(code, out var t))
        {
            return code;
        }

        var zh = Culture.Name.StartsWith("zh", StringComparison.OrdinalIgnoreCase);
        return string.Format(CultureInfo.InvariantCulture, zh ? t.Zh : t.En, args);
    }
}
