namespace PmacStream.Pmac;

/// <summary>The controller's <c>ERRnnn</c> numbers with the manual's texts (Turbo PMAC Software Reference).</summary>
public static class PmacErrors
{
    private static readonly string[] Texts =
    [
        "",
        "command not allowed during program execution",
        "password error",
        "data error or unrecognized command",
        "illegal character",
        "command not allowed unless buffer is open",
        "no room in buffer for command",
        "buffer already in use",
        "MACRO auxiliary communications error",
        "program structural error",
        "both overtravel limits set for a motor in the C.S.",
        "previous move not completed",
        "a motor in the C.S. is open-loop",
        "a motor in the C.S. is not activated",
        "no motors in the C.S.",
        "not pointing to valid program buffer",
        "running improperly structured program",
        "trying to resume after H or Q with motors out of stopped position",
        "phase-reference conflict",
        "illegal position-change command while moves stored in CCBUFFER",
    ];

    /// <summary>Unknown command (data error).</summary>
    public const int UnknownCommand = 3;

    /// <summary>Illegal character (bytes above 127).</summary>
    public const int IllegalCharacter = 4;

    /// <summary>Program line with no open buffer.</summary>
    public const int BufferNotOpen = 5;

    /// <summary>No room in buffer.</summary>
    public const int NoRoom = 6;

    /// <summary>Buffer already open on another port.</summary>
    public const int BufferInUse = 7;

    /// <summary>Not allowed while a program runs.</summary>
    public const int NotAllowedWhileRunning = 1;

    /// <summary>Not pointing to a valid program buffer.</summary>
    public const int NoValidProgram = 15;

    /// <summary>The manual's text for an error number.</summary>
    public static string Describe(int number) =>
        number > 0 && number < Texts.Length ? Texts[number] : $"controller error {number}";
}

/// <summary>A controller answered <c>ERRnnn</c>: the number, the manual's text and the command that caused it.</summary>
public sealed class PmacErrorException : Exception
{
    /// <summary>Creates the error for a command.</summary>
    public PmacErrorException(int number, string command, int? lineInBatch = null)
        : base($"ERR{number:000} ({PmacErrors.Describe(number)}) for '{command}'" + (lineInBatch is { } l ? $" at line {l}" : string.Empty))
    {
        Number = number;
        Command = command;
        LineInBatch = lineInBatch;
    }

    /// <summary>The ERR number.</summary>
    public int Number { get; }

    /// <summary>The command or program line the controller refused.</summary>
    public string Command { get; }

    /// <summary>For downloads: the 0-based index of the failing line within what was sent, when known.</summary>
    public int? LineInBatch { get; }

    /// <summary>
    /// For downloads with several packets in flight: lines of later packets the controller stored although an earlier
    /// line was refused. They sit in the buffer behind a gap (the refused line and the rest of its packet), so
    /// execution must be stopped before it reaches them. 0: nothing was stored after the refusal.
    /// </summary>
    public int LinesStoredAfterGap { get; init; }
}

/// <summary>The link to the controller failed (timeout, closed connection, bad framing). The job stays resumable.</summary>
public sealed class PmacLinkException : Exception
{
    /// <summary>Creates the exception.</summary>
    public PmacLinkException(string message, Exception? inner = null)
        : base(message, inner)
    {
    }
}
