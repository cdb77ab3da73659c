namespace PmacStream.GCode;

/// <summary>
/// Bounds on what one line of a program can cost, so memory stays small whatever the input: a line of a megabyte of
/// junk is read (the reader cuts lines at <see cref="GCodeReader.MaxLineLength"/>), but only so many of its words are
/// interpreted and only so many of its findings are listed; the rest are counted (the summary says how many).
/// </summary>
public static class FindingLimits
{
    /// <summary>Findings (errors and warnings) listed for one line; more are counted, not listed.</summary>
    public const int PerLine = 64;

    /// <summary>Address words read from one line; a line with more is an error (E128) and the rest of it is not read.</summary>
    public const int WordsPerLine = 256;

    /// <summary>
    /// Findings the checker holds while it cannot yet tell whether the program numbers its blocks (W002); past this the
    /// program is taken as un-numbered and they are listed.
    /// </summary>
    public const int Held = 4_096;
}
