using System.Text.Json;
using PmacStream.GCode;

namespace PmacStream.Jobs;

/// <summary>
/// What the settings file says about this station rather than about a run: the store it records in (<c>store</c>),
/// its name (<c>station</c>), and its machine leases' heartbeat and expiry (<c>leaseHeartbeatSeconds</c>, default 10;
/// <c>leaseExpirySeconds</c>, default 60, at most 60 so a dead station's lease frees itself within a minute). Kept
/// apart from <see cref="RunSettings"/> because a job record keeps a copy of those, and the store may name a password.
/// </summary>
/// <param name="Store">The store's location from the file, or null.</param>
/// <param name="Station">The station's name from the file, or null.</param>
/// <param name="LeaseHeartbeat">How often a held lease is renewed.</param>
/// <param name="LeaseExpiry">How long after its last heartbeat a lease frees itself.</param>
public sealed record StationSettings(string? Store, string? Station, TimeSpan LeaseHeartbeat, TimeSpan LeaseExpiry)
{
    /// <summary>The property names this record reads (the run settings' reader skips them).</summary>
    public static readonly IReadOnlyList<string> Names = ["store", "station", "leaseHeartbeatSeconds", "leaseExpirySeconds"];

    /// <summary>No file: no store or station named, a heartbeat every 10 s, expiry 60 s after the last one.</summary>
    public static StationSettings Default { get; } = new(null, null, TimeSpan.FromSeconds(10), TimeSpan.FromSeconds(60));

    /// <summary>The station's name: <paramref name="option"/> (<c>--station</c>), else the file's, else the host name.</summary>
    public string StationName(string? option) => option is { Length: > 0 } ? option : Station is { Length: > 0 } s ? s : Environment.MachineName;

    /// <summary>Reads the file named (or the default one when it exists); a bad value is <c>FILE:LINE:COL: error R003: message</c>.</summary>
    /// <exception cref="RunSettingsException">A value of the wrong type or out of range.</exception>
    /// <exception cref="IOException">A named file cannot be read.</exception>
    public static StationSettings Load(string? path = null)
    {
        var file = path ?? RunSettingsFile.DefaultPath;
        if (path is null && !File.Exists(file))
        {
            return Default;
        }

        if (!File.Exists(file))
        {
            throw new FileNotFoundException($"{file}: no such settings file", file);
        }

        return Read(File.ReadAllBytes(file), file);
    }

    /// <summary>Reads the station's properties of a settings file's JSON (the run settings' reader checks the rest).</summary>
    /// <exception cref="RunSettingsException">Not JSON, or a value of the wrong type or out of range.</exception>
    public static StationSettings Read(ReadOnlySpan<byte> json, string source)
    {
        var s = Default;
        var reader = new Utf8JsonReader(json, new JsonReaderOptions { CommentHandling = JsonCommentHandling.Skip, AllowTrailingCommas = true });
        try
        {
            if (!reader.Read() || reader.TokenType != JsonTokenType.StartObject)
            {
                return s; // the run settings' reader says what is wrong with it
            }

            while (reader.Read() && reader.TokenType != JsonTokenType.EndObject)
            {
                var name = reader.GetString()!;
                reader.Read();
                var at = reader.TokenStartIndex;
                try
                {
                    s = name switch
                    {
                        "store" => s with { Store = Text(ref reader) },
                        "station" => s with { Station = Text(ref reader) },
                        "leaseHeartbeatSeconds" => s with { LeaseHeartbeat = Seconds(ref reader, 0.1, 60) },
                        "leaseExpirySeconds" => s with { LeaseExpiry = Seconds(ref reader, 1, 60) },
                        _ => s,
                    };
                }
                catch (Exception e) when (e is InvalidOperationException or FormatException or ArgumentException)
                {
                    throw new RunSettingsException(source, At(json, at, $"{name}: {e.Message}"));
                }

                reader.Skip();
            }
        }
        catch (JsonException)
        {
            return s; // the run settings' reader reports malformed JSON with its position
        }

        return s.LeaseHeartbeat < s.LeaseExpiry
            ? s
            : throw new RunSettingsException(source, new Diagnostic(Severity.Error, RunSettingsFile.BadValueCode, 1, 1,
                $"leaseHeartbeatSeconds ({s.LeaseHeartbeat.TotalSeconds:0.###}) must be shorter than leaseExpirySeconds ({s.LeaseExpiry.TotalSeconds:0.###})"));
    }

    private static string Text(ref Utf8JsonReader r) =>
        r.TokenType == JsonTokenType.String ? r.GetString()! : throw new InvalidOperationException($"expected a string, got {r.TokenType.ToString().ToLowerInvariant()}");

    private static TimeSpan Seconds(ref Utf8JsonReader r, double min, double max)
    {
        if (r.TokenType != JsonTokenType.Number)
        {
            throw new InvalidOperationException($"expected a number, got {r.TokenType.ToString().ToLowerInvariant()}");
        }

        var v = r.GetDouble();
        return v >= min && v <= max ? TimeSpan.FromSeconds(v) : throw new ArgumentException($"must be {min} to {max} seconds (got {v})");
    }

    private static Diagnostic At(ReadOnlySpan<byte> json, long offset, string message)
    {
        int line = 1, column = 1;
        for (var i = 0; i < offset && i < json.Length; i++)
        {
            (line, column) = json[i] == (byte)'\n' ? (line + 1, 1) : (line, column + 1);
        }

        return new Diagnostic(Severity.Error, RunSettingsFile.BadValueCode, line, column, message);
    }
}
