using System.Text;
using System.Text.Json;
using PmacStream.GCode;
using PmacStream.Preparation;
using Serilog;

namespace PmacStream.Jobs;

/// <summary>
/// <see cref="RunSettings"/> as JSON: a settings file (<c>--settings FILE</c>, or <see cref="DefaultPath"/> when it
/// exists) and the copy a job record keeps. A flat object; every property is optional and overrides the settings it
/// is read over:
/// <code>
/// { "bufferWords": 16000, "windowStart": 0.6, "windowEnd": 0.7, "tickMs": 50, "safeZMode": "fixed", "safeZ": 10, "clearance": 5,
///   "blocksPerChunk": 1000, "chunkWords": 6400, "trackVariable": "M0", "feedVariable": "P500", "tracking": "exact", ... }
/// </code>
/// The chunk shape's properties (<see cref="ChunkShape.JsonNames"/>: <c>blocksPerChunk</c>, <c>chunkWords</c>,
/// <c>wordsPerBlock</c>, <c>bytesPerWord</c>, <c>trackVariable</c>, <c>tracking</c>, <c>feed</c>, <c>feedVariable</c>,
/// <c>programTail</c>, <c>keepN</c>, <c>blockDelete</c>) are read by the shape's own JSON names, so a new one needs
/// nothing here; <c>linesPerChunk</c>, the old name of <c>blocksPerChunk</c>, is still read, with a warning.
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

    /// <summary>A warning: a property under its old name (still read).</summary>
    public const string OldNameCode = "R004";

    /// <summary>The old name of <c>blocksPerChunk</c> (it always counted blocks, not text lines).</summary>
    public const string OldBlocksPerChunkName = "linesPerChunk";

    /// <summary>The properties of the settings themselves; the rest are the chunk shape's.</summary>
    private static readonly string[] RunNames = ["bufferWords", "packetsInFlight", "bufferWordsCap", "windowStart", "windowEnd", "tickMs", "safeZMode", "safeZ", "clearance"];

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
            return File.Exists(fallback) ? Read(RunSettings.Default, File.ReadAllBytes(fallback), fallback, Warn) : RunSettings.Default;
        }

        if (!File.Exists(path))
        {
            throw new FileNotFoundException($"{path}: no such settings file", path);
        }

        return Read(RunSettings.Default, File.ReadAllBytes(path), path, Warn);
    }

    private static void Warn(string message) => Log.Warning("{Message:l}", message);

    /// <summary>
    /// Reads <paramref name="json"/> over <paramref name="baseSettings"/>; <paramref name="source"/> names it in errors,
    /// <paramref name="warn"/> hears of old names (as <c>FILE:LINE:COL: warning R004: message</c>).
    /// </summary>
    /// <exception cref="RunSettingsException">Not valid, with the position of the fault.</exception>
    public static RunSettings Read(RunSettings baseSettings, ReadOnlySpan<byte> json, string source, Action<string>? warn = null)
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
                if (name == OldBlocksPerChunkName)
                {
                    warn?.Invoke(At(source, bytes, at, Severity.Warning, OldNameCode, $"'{OldBlocksPerChunkName}' is now 'blocksPerChunk' (it counts blocks, not text lines); the old name still works"));
                    name = "blocksPerChunk";
                }

                if (StationSettings.Names.Contains(name))
                {
                    reader.Skip(); // the station's settings (store, station, leases): StationSettings reads them
                    continue;
                }

                s = RunNames.Contains(name) ? ReadRunProperty(s, name, ref reader, source, bytes, valueAt) : ReadShapeProperty(s, name, ref reader, source, bytes, at, valueAt);
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

    /// <summary>A property of the chunk shape, read by the shape's own JSON names and checked by its own rules.</summary>
    private static RunSettings ReadShapeProperty(RunSettings s, string name, ref Utf8JsonReader reader, string source, ReadOnlySpan<byte> bytes, long at, long valueAt)
    {
        var value = JsonElement.ParseValue(ref reader);
        try
        {
            var shape = s.Shape.WithJson(name, value) ?? throw Fault(source, bytes, at, UnknownCode,
                $"unknown setting '{name}' (known: {string.Join(", ", RunNames.Concat(ChunkShape.JsonNames).Concat(StationSettings.Names))})");
            shape.Validate();
            return s with { Shape = shape };
        }
        catch (JsonException)
        {
            throw Fault(source, bytes, valueAt, BadValueCode, $"{name}: expected {ChunkShape.ExpectedJson(name)}, got {value.ValueKind.ToString().ToLowerInvariant()}");
        }
        catch (ArgumentException e)
        {
            throw Fault(source, bytes, valueAt, BadValueCode, e.Message);
        }
    }

    /// <summary>A property of the run (buffer, window, tick, safe Z...), its value checked as it is read.</summary>
    private static RunSettings ReadRunProperty(RunSettings s, string name, ref Utf8JsonReader reader, string source, ReadOnlySpan<byte> bytes, long valueAt)
    {
        try
        {
            return Apply(s, name, ref reader);
        }
        catch (InvalidOperationException)
        {
            var expected = name is "safeZMode" ? "a string" : "a number";
            throw Fault(source, bytes, valueAt, BadValueCode, $"{name}: expected {expected}, got {reader.TokenType.ToString().ToLowerInvariant()}");
        }
        catch (Exception e) when (e is FormatException or ArgumentException)
        {
            throw Fault(source, bytes, valueAt, BadValueCode, $"{name}: {e.Message}");
        }
    }

    /// <summary>
    /// The settings as the JSON <see cref="Read"/> takes: every property, the chunk shape's too unless
    /// <paramref name="withShape"/> is off (a job record: its shape is its split's, kept once, in the manifest).
    /// </summary>
    public static string ToJson(RunSettings settings, bool withShape = true)
    {
        ArgumentNullException.ThrowIfNull(settings);
        using var ms = new MemoryStream();
        using (var w = new Utf8JsonWriter(ms))
        {
            w.WriteStartObject();
            w.WriteNumber("bufferWords", settings.BufferWords);
            w.WriteNumber("packetsInFlight", settings.PacketsInFlight);
            w.WriteNumber("bufferWordsCap", settings.BufferWordsCap);
            w.WriteNumber("windowStart", settings.WindowStart);
            w.WriteNumber("windowEnd", settings.WindowEnd);
            w.WriteNumber("tickMs", settings.TickPeriod.TotalMilliseconds);
            w.WriteString("safeZMode", settings.SafeZMode == SafeZMode.Fixed ? "fixed" : "highest");
            w.WriteNumber("safeZ", settings.SafeZ);
            w.WriteNumber("clearance", settings.Clearance);
            if (withShape)
            {
                settings.Shape.WriteProperties(w);
            }

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

    private static RunSettings Apply(RunSettings s, string name, ref Utf8JsonReader r) => name switch
    {
        "bufferWords" => s with { BufferWords = Positive(r.GetInt32()) },
        "packetsInFlight" => s with { PacketsInFlight = r.GetInt32() is >= 1 and <= 64 and var n ? n : throw new ArgumentException("must be 1 to 64") },
        "bufferWordsCap" => s with { BufferWordsCap = r.GetInt32() is >= 0 and var c ? c : throw new ArgumentException("must be 0 (no cap) or more") },
        "windowStart" => s with { WindowStart = Fraction(r.GetDouble()) },
        "windowEnd" => s with { WindowEnd = Fraction(r.GetDouble()) },
        "tickMs" => s with { TickPeriod = TimeSpan.FromMilliseconds(Positive(r.GetDouble())) },
        "safeZMode" => s with { SafeZMode = ParseSafeZMode(r.GetString() ?? string.Empty) },
        "safeZ" => s with { SafeZ = r.GetDouble() },
        "clearance" => s with { Clearance = r.GetDouble() >= 0 ? r.GetDouble() : throw new ArgumentException("must be 0 or more") },
        _ => throw new InvalidOperationException($"{name} is not a run setting"),
    };

    private static int Positive(int v) => v >= 1 ? v : throw new ArgumentException($"must be 1 or more (got {v})");

    private static double Positive(double v) => v > 0 ? v : throw new ArgumentException($"must be more than 0 (got {v})");

    private static double Fraction(double v) => v is >= 0 and <= 1 ? v : throw new ArgumentException($"must be a fraction of a chunk, 0 to 1 (got {v})");

    private static RunSettingsException Fault(string source, ReadOnlySpan<byte> json, long offset, string code, string message) =>
        new(source, Position(json, offset, Severity.Error, code, message));

    private static string At(string source, ReadOnlySpan<byte> json, long offset, Severity severity, string code, string message) =>
        Position(json, offset, severity, code, message).Format(source);

    private static Diagnostic Position(ReadOnlySpan<byte> json, long offset, Severity severity, string code, string message)
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

        return new Diagnostic(severity, code, line, column, message);
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
