using System.Text;
using System.Text.Json;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Jobs;

/// <summary>
/// <see cref="RunSettings"/> as JSON: a settings file (<c>--settings FILE</c>, or <see cref="DefaultPath"/> when it
/// exists) and the copy a job record keeps. A flat object; every property is optional and overrides the settings it
/// is read over:
/// <code>
/// { "linesPerChunk": 1000, "bufferWords": 16000, "chunkWords": 6400, "windowStart": 0.6, "windowEnd": 0.7,
///   "trackVariable": "M0", "feedVariable": "P500", "tickMs": 50, "safeZMode": "fixed", "safeZ": 10, "clearance": 5 }
/// </code>
/// Read by hand with the reader's positions, so a bad file is reported as <c>FILE:LINE:COL: error R00n: message</c>.
/// </summary>
public static class RunSettingsFile
{
    /// <summary>Not JSON, or not an object.</summary>
    public const string MalformedCode = "R001";

    /// <summary>A property this version does not know (a typo would otherwise be ignored silently).</summary>
    public const string UnknownCode = "R002";

    /// <summary>A value of the wrong type or out of range, or settings that cannot work together.</summary>
    public const string BadValueCode = "R003";

    /// <summary>The settings file both faces read when none is named: <c>$PMACSTREAM_SETTINGS</c>, else <c>~/.pmacstream/settings.json</c>.</summary>
    public static string DefaultPath =>
        Environment.GetEnvironmentVariable("PMACSTREAM_SETTINGS") is { Length: > 0 } env
            ? env
            : Path.Combine(Environment.GetFolderPath(Environment.SpecialFolder.UserProfile), ".pmacstream", "settings.json");

    /// <summary>
    /// The settings a face starts from: <paramref name="path"/> read over the defaults; with no path, the default
    /// file when it exists, else the defaults.
    /// </summary>
    /// <exception cref="RunSettingsException">The file is not valid.</exception>
    /// <exception cref="IOException">A named file cannot be read.</exception>
    public static RunSettings Load(string? path = null)
    {
        if (path is null)
        {
            var fallback = DefaultPath;
            return File.Exists(fallback) ? Read(RunSettings.Default, File.ReadAllBytes(fallback), fallback) : RunSettings.Default;
        }

        if (!File.Exists(path))
        {
            throw new FileNotFoundException($"{path}: no such settings file", path);
        }

        return Read(RunSettings.Default, File.ReadAllBytes(path), path);
    }

    /// <summary>Reads <paramref name="json"/> over <paramref name="baseSettings"/>; <paramref name="source"/> names it in errors.</summary>
    /// <exception cref="RunSettingsException">Not valid, with the position of the fault.</exception>
    public static RunSettings Read(RunSettings baseSettings, ReadOnlySpan<byte> json, string source)
    {
        ArgumentNullException.ThrowIfNull(baseSettings);
        var s = baseSettings;
        var reader = new Utf8JsonReader(json, new JsonReaderOptions { CommentHandling = JsonCommentHandling.Skip, AllowTrailingCommas = true });
        var bytes = json;
        try
        {
            if (!reader.Read() || reader.TokenType != JsonTokenType.StartObject)
            {
                throw Fault(source, bytes, reader.TokenStartIndex, MalformedCode, "expected a JSON object of settings");
            }

            while (reader.Read() && reader.TokenType != JsonTokenType.EndObject)
            {
                var name = reader.GetString()!;
                var at = reader.TokenStartIndex;
                reader.Read();
                var valueAt = reader.TokenStartIndex;
                try
                {
                    s = Apply(s, name, ref reader) ?? throw Fault(source, bytes, at, UnknownCode,
                        $"unknown setting '{name}' (known: linesPerChunk, bufferWords, chunkWords, windowStart, windowEnd, trackVariable, feedVariable, tickMs, safeZMode, safeZ, clearance)");
                }
                catch (InvalidOperationException)
                {
                    var expected = name is "trackVariable" or "feedVariable" or "safeZMode" ? "a string" : "a number";
                    throw Fault(source, bytes, valueAt, BadValueCode, $"{name}: expected {expected}, got {reader.TokenType.ToString().ToLowerInvariant()}");
                }
                catch (Exception e) when (e is FormatException or ArgumentException)
                {
                    throw Fault(source, bytes, valueAt, BadValueCode, $"{name}: {e.Message}");
                }
            }
        }
        catch (JsonException e)
        {
            var d = new Diagnostic(Severity.Error, MalformedCode, (int)(e.LineNumber ?? 0) + 1, (int)(e.BytePositionInLine ?? 0) + 1, "not valid JSON: " + FirstSentence(e.Message));
            throw new RunSettingsException(source, d);
        }

        try
        {
            s.Validate();
        }
        catch (ArgumentException e)
        {
            throw new RunSettingsException(source, new Diagnostic(Severity.Error, BadValueCode, 1, 1, e.Message));
        }

        return s;
    }

    /// <summary>The settings as the JSON <see cref="Read"/> takes (every property written).</summary>
    public static string ToJson(RunSettings settings)
    {
        ArgumentNullException.ThrowIfNull(settings);
        using var ms = new MemoryStream();
        using (var w = new Utf8JsonWriter(ms))
        {
            w.WriteStartObject();
            w.WriteNumber("linesPerChunk", settings.LinesPerChunk);
            w.WriteNumber("bufferWords", settings.BufferWords);
            w.WriteNumber("chunkWords", settings.ChunkWords);
            w.WriteNumber("windowStart", settings.WindowStart);
            w.WriteNumber("windowEnd", settings.WindowEnd);
            w.WriteString("trackVariable", settings.TrackVariable);
            w.WriteString("feedVariable", settings.FeedVariable);
            w.WriteNumber("tickMs", settings.TickPeriod.TotalMilliseconds);
            w.WriteString("safeZMode", settings.SafeZMode == SafeZMode.Fixed ? "fixed" : "highest");
            w.WriteNumber("safeZ", settings.SafeZ);
            w.WriteNumber("clearance", settings.Clearance);
            w.WriteEndObject();
        }

        return Encoding.UTF8.GetString(ms.ToArray());
    }

    /// <summary>Parses a safe-Z mode as the CLI and settings files spell it (<c>fixed</c>, <c>highest</c>).</summary>
    public static SafeZMode ParseSafeZMode(string text) => text.Trim().ToLowerInvariant() switch
    {
        "fixed" => SafeZMode.Fixed,
        "highest" => SafeZMode.HighestSoFar,
        var other => throw new FormatException($"expected fixed or highest, got '{other}'"),
    };

    private static RunSettings? Apply(RunSettings s, string name, ref Utf8JsonReader r) => name switch
    {
        "linesPerChunk" => s with { LinesPerChunk = Positive(r.GetInt32()) },
        "bufferWords" => s with { BufferWords = Positive(r.GetInt32()) },
        "chunkWords" => s with { ChunkWords = Positive(r.GetInt32()) },
        "windowStart" => s with { WindowStart = Fraction(r.GetDouble()) },
        "windowEnd" => s with { WindowEnd = Fraction(r.GetDouble()) },
        "trackVariable" => s with { TrackVariable = r.GetString() ?? throw new FormatException("expected a variable name such as M0") },
        "feedVariable" => s with { FeedVariable = r.GetString() ?? throw new FormatException("expected a variable name such as P500") },
        "tickMs" => s with { TickPeriod = TimeSpan.FromMilliseconds(Positive(r.GetDouble())) },
        "safeZMode" => s with { SafeZMode = ParseSafeZMode(r.GetString() ?? string.Empty) },
        "safeZ" => s with { SafeZ = r.GetDouble() },
        "clearance" => s with { Clearance = r.GetDouble() >= 0 ? r.GetDouble() : throw new ArgumentException("must be 0 or more") },
        _ => null,
    };

    private static int Positive(int v) => v >= 1 ? v : throw new ArgumentException($"must be 1 or more (got {v})");

    private static double Positive(double v) => v > 0 ? v : throw new ArgumentException($"must be more than 0 (got {v})");

    private static double Fraction(double v) => v is >= 0 and <= 1 ? v : throw new ArgumentException($"must be a fraction of a chunk, 0 to 1 (got {v})");

    private static RunSettingsException Fault(string source, ReadOnlySpan<byte> json, long offset, string code, string message)
    {
        // Line and column of a byte offset (columns count bytes, as the checker's do).
        int line = 1, column = 1;
        for (var i = 0; i < offset && i < json.Length; i++)
        {
            if (json[i] == (byte)'\n')
            {
                line++;
                column = 1;
            }
            else
            {
                column++;
            }
        }

        return new RunSettingsException(source, new Diagnostic(Severity.Error, code, line, column, message));
    }

    private static string FirstSentence(string message)
    {
        var i = message.IndexOf(" LineNumber", StringComparison.Ordinal);
        return (i > 0 ? message[..i] : message).TrimEnd(' ', '.');
    }
}

/// <summary>A settings file that cannot be used; <see cref="Exception.Message"/> is <c>FILE:LINE:COL: error CODE: message</c>.</summary>
public sealed class RunSettingsException(string source, Diagnostic diagnostic) : Exception(diagnostic.Format(source))
{
    /// <summary>The file (or other source) read.</summary>
    public string SettingsPath { get; } = source;

    /// <summary>What is wrong and where.</summary>
    public Diagnostic Diagnostic { get; } = diagnostic;
}
