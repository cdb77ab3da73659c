using SkiaSharp;

namespace PmacStream.Preview;

/// <summary>
/// The legend's fonts: a sans-serif family picked by name (the first installed of <see cref="Families"/>, else the
/// system default), and for each character it lacks, such as the Chinese labels, the typeface the system's font
/// manager matches for that character (fontconfig on Linux). Text is drawn in runs of one typeface each on a common
/// baseline.
/// </summary>
internal sealed class LegendFont : IDisposable
{
    /// <summary>Families tried in order for the Latin text and numbers.</summary>
    public static readonly string[] Families = ["DejaVu Sans", "Noto Sans", "Liberation Sans", "Segoe UI", "Arial", "Helvetica", "Noto Sans CJK SC"];

    // Chinese first, so that a character shared by the CJK languages is drawn with Simplified Chinese forms.
    private static readonly string[] Locales = ["zh-Hans", "zh-CN", "zh"];

    private readonly SKFontManager _manager;
    private readonly List<SKFont> _fonts = new();
    private readonly Dictionary<int, int> _fontOf = new();
    private readonly float _ascent;

    /// <summary>Fonts of <paramref name="size"/> pixels from <paramref name="manager"/> (default: the system's).</summary>
    public LegendFont(float size, SKFontManager? manager = null)
    {
        _manager = manager ?? SKFontManager.Default;
        SKTypeface? primary = null;
        foreach (var family in Families)
        {
            primary = _manager.MatchFamily(family, SKFontStyle.Normal);
            if (primary is not null && Has(primary, 'A'))
            {
                break;
            }

            primary?.Dispose();
            primary = null;
        }

        primary ??= _manager.MatchCharacter('A') ?? SKTypeface.CreateDefault();
        _fonts.Add(NewFont(primary, size));
        _fonts[0].GetFontMetrics(out var metrics);
        _ascent = -metrics.Ascent;
        LineHeight = metrics.Descent - metrics.Ascent;
    }

    /// <summary>The family of the Latin text.</summary>
    public string Family => _fonts[0].Typeface.FamilyName;

    /// <summary>Families used so far for characters the first one lacks.</summary>
    public IEnumerable<string> Fallbacks => _fonts.Skip(1).Select(f => f.Typeface.FamilyName);

    /// <summary>Ascent plus descent of the Latin font, in pixels.</summary>
    public float LineHeight { get; }

    /// <summary>True when some installed font has a glyph for every character of <paramref name="text"/>.</summary>
    public bool CanDraw(string text)
    {
        foreach (var (_, font) in Runs(text))
        {
            if (font < 0)
            {
                return false;
            }
        }

        return true;
    }

    /// <summary>Width of <paramref name="text"/> in pixels.</summary>
    public float Measure(string text)
    {
        var width = 0f;
        foreach (var (run, font) in Runs(text))
        {
            width += _fonts[Math.Max(0, font)].MeasureText(run);
        }

        return width;
    }

    /// <summary>Draws <paramref name="text"/> with its top (the Latin font's ascent) at <paramref name="top"/>; returns the width drawn.</summary>
    public float Draw(SKCanvas canvas, string text, float x, float top, SKPaint paint)
    {
        var baseline = top + _ascent;
        var cx = x;
        foreach (var (run, font) in Runs(text))
        {
            var f = _fonts[Math.Max(0, font)];
            canvas.DrawText(run, cx, baseline, SKTextAlign.Left, f, paint);
            cx += f.MeasureText(run);
        }

        return cx - x;
    }

    /// <inheritdoc />
    public void Dispose()
    {
        foreach (var f in _fonts)
        {
            f.Typeface.Dispose();
            f.Dispose();
        }
    }

    private static bool Has(SKTypeface typeface, int codepoint)
    {
        using var font = new SKFont(typeface);
        return font.ContainsGlyph(codepoint);
    }

    private static SKFont NewFont(SKTypeface typeface, float size) =>
        new(typeface, size) { Edging = SKFontEdging.Antialias, Subpixel = true, Hinting = SKFontHinting.Slight };

    /// <summary>The text cut into runs of one font each (index into the fonts; -1 where no installed font has the character).</summary>
    private IEnumerable<(string Run, int Font)> Runs(string text)
    {
        var start = 0;
        var current = int.MinValue;
        var index = 0;
        while (index < text.Length)
        {
            var cp = char.ConvertToUtf32(text, index);
            var width = char.IsSurrogatePair(text, index) ? 2 : 1;
            var font = char.IsWhiteSpace(text, index) && current != int.MinValue ? current : FontFor(cp);
            if (font != current && index > start)
            {
                yield return (text[start..index], current);
                start = index;
            }

            current = font;
            index += width;
        }

        if (index > start)
        {
            yield return (text[start..], current);
        }
    }

    private int FontFor(int codepoint)
    {
        if (_fontOf.TryGetValue(codepoint, out var known))
        {
            return known;
        }

        var found = -1;
        for (var i = 0; i < _fonts.Count && found < 0; i++)
        {
            if (_fonts[i].ContainsGlyph(codepoint))
            {
                found = i;
            }
        }

        if (found < 0)
        {
            var typeface = _manager.MatchCharacter(_fonts[0].Typeface.FamilyName, SKFontStyle.Normal, Locales, codepoint);
            if (typeface is not null && Has(typeface, codepoint))
            {
                _fonts.Add(NewFont(typeface, _fonts[0].Size));
                found = _fonts.Count - 1;
            }
            else
            {
                typeface?.Dispose();
            }
        }

        _fontOf[codepoint] = found;
        return found;
    }
}
