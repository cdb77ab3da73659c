using System.Globalization;
using System.Runtime.InteropServices;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <summary>
/// The words of a line the host's conversion writes, recorded as it writes them, exactly as the lexer would read the
/// line back (letter, value, column, number span), so the splitter does not lex the line again. A number the lexer
/// reads its own way (more than 15 characters) ends the recording: that line is lexed.
/// </summary>
internal sealed class WrittenWords
{
    private readonly List<GWord> _words = [];
    private bool _recording;

    /// <summary>The words recorded since <see cref="Begin"/>.</summary>
    public ReadOnlySpan<GWord> Words => CollectionsMarshal.AsSpan(_words);

    /// <summary>A new line starts (at column 1 of the builder).</summary>
    public void Begin()
    {
        _words.Clear();
        _recording = true;
    }

    /// <summary>The line is written: true when every word of it was recorded.</summary>
    public bool End()
    {
        var complete = _recording;
        _recording = false;
        return complete;
    }

    /// <summary>Appends <paramref name="value"/> as <see cref="HostConversion.Num"/> writes it, without a string for it.</summary>
    public static void AppendNumber(StringBuilder sb, double value)
    {
        Span<char> text = stackalloc char[24];
        if (!Math.Round(value, 6).TryFormat(text, out var n, "0.######", CultureInfo.InvariantCulture))
        {
            sb.Append(HostConversion.Num(value));
        }
        else if (n == 2 && text[0] == '-' && text[1] == '0')
        {
            sb.Append('0');
        }
        else
        {
            sb.Append(text[..n]);
        }
    }

    /// <summary>Records the word written at <paramref name="at"/> (its letter) to the end of <paramref name="sb"/>, while a line is recorded.</summary>
    public void Record(StringBuilder sb, int at)
    {
        var start = at + 1;
        var length = sb.Length - start;
        // Up to 15 characters the number has at most 15 digits, which the lexer reads as mantissa over a power of ten.
        if (!_recording || length is > 15 or 0)
        {
            _recording = false;
            return;
        }

        var negative = sb[start] == '-';
        long mantissa = 0;
        var scale = -1;
        var digits = 0;
        for (var i = negative ? start + 1 : start; i < sb.Length; i++)
        {
            var c = sb[i];
            if (c == '.' && scale < 0)
            {
                scale = 0;
            }
            else if (char.IsAsciiDigit(c))
            {
                mantissa = (mantissa * 10) + (c - '0');
                scale += scale >= 0 ? 1 : 0;
                digits++;
            }
            else
            {
                _recording = false;
                return;
            }
        }

        if (digits == 0)
        {
            _recording = false;
            return;
        }

        _words.Add(new GWord(sb[at], LineLexer.ShortNumber(mantissa, Math.Max(0, scale), negative), at + 1, start, length, WasLowercase: false));
    }
}
