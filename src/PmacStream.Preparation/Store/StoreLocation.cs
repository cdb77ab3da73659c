namespace PmacStream.Preparation.Store;

/// <summary>The database engines a store runs on.</summary>
public enum StoreEngine
{
    /// <summary>One SQLite file on this PC (the default: no set-up).</summary>
    Sqlite,

    /// <summary>A PostgreSQL database a shop shares.</summary>
    Postgres,
}

/// <summary>
/// Where the store (programs, jobs, checkpoints) lives: <c>sqlite:PATH</c> (a relative path is relative to the current
/// folder), <c>postgres://user@host:port/db</c>, or an Npgsql connection string (<c>Host=...;Database=...</c>). A
/// password may come in the URI or the connection string, or from PostgreSQL's own <c>PGPASSWORD</c> /
/// <c>PGPASSFILE</c>; <see cref="Display"/> never shows it.
/// </summary>
public sealed record StoreLocation
{
    /// <summary>The environment variable that names the store when no option does.</summary>
    public const string EnvironmentVariable = "PMACSTREAM_STORE";

    private StoreLocation(StoreEngine engine, string target, string display)
    {
        Engine = engine;
        Target = target;
        Display = display;
    }

    /// <summary>The engine.</summary>
    public StoreEngine Engine { get; }

    /// <summary>The SQLite file's full path, or the Npgsql connection string (may hold a password: never log it).</summary>
    public string Target { get; }

    /// <summary>The location as shown to people and written to logs: without any password.</summary>
    public string Display { get; }

    /// <summary>The default store: <c>~/.pmacstream/store.db</c>.</summary>
    public static string DefaultSqlitePath =>
        Path.Combine(Environment.GetFolderPath(Environment.SpecialFolder.UserProfile), ".pmacstream", "store.db");

    /// <summary>An SQLite store file (relative to the current folder).</summary>
    public static StoreLocation Sqlite(string path)
    {
        var full = Path.GetFullPath(path);
        return new StoreLocation(StoreEngine.Sqlite, full, "sqlite:" + full);
    }

    /// <summary>
    /// Picks the store: <paramref name="store"/> (<c>--store</c>), else <paramref name="jobDb"/> (<c>--job-db</c>, an
    /// SQLite file), else <paramref name="fromSettings"/> (the settings file's <c>store</c>), else
    /// <c>$PMACSTREAM_STORE</c>, else <c>$PMACSTREAM_JOB_DB</c> (an older way to name the SQLite file), else the default file.
    /// </summary>
    /// <exception cref="FormatException">The location cannot be read.</exception>
    public static StoreLocation Resolve(string? store = null, string? jobDb = null, string? fromSettings = null)
    {
        if (store is { Length: > 0 })
        {
            return Parse(store);
        }

        if (jobDb is { Length: > 0 })
        {
            return Sqlite(jobDb);
        }

        if (fromSettings is { Length: > 0 })
        {
            return Parse(fromSettings);
        }

        if (Environment.GetEnvironmentVariable(EnvironmentVariable) is { Length: > 0 } env)
        {
            return Parse(env);
        }

        return Environment.GetEnvironmentVariable("PMACSTREAM_JOB_DB") is { Length: > 0 } legacy ? Sqlite(legacy) : Sqlite(DefaultSqlitePath);
    }

    /// <summary>Reads <c>sqlite:PATH</c>, <c>postgres://...</c>, <c>postgresql://...</c>, an Npgsql connection string, or a bare path (SQLite).</summary>
    /// <exception cref="FormatException">A URI that cannot be read.</exception>
    public static StoreLocation Parse(string text)
    {
        ArgumentNullException.ThrowIfNull(text);
        var t = text.Trim();
        if (t.StartsWith("sqlite:", StringComparison.OrdinalIgnoreCase))
        {
            var path = t["sqlite:".Length..];
            return path.Length == 0 ? throw new FormatException("sqlite: needs a file path (sqlite:PATH)") : Sqlite(path);
        }

        if (t.StartsWith("postgres://", StringComparison.OrdinalIgnoreCase) || t.StartsWith("postgresql://", StringComparison.OrdinalIgnoreCase))
        {
            return FromUri(t);
        }

        if (t.Contains('=', StringComparison.Ordinal) && t.Contains("host", StringComparison.OrdinalIgnoreCase))
        {
            var b = new Npgsql.NpgsqlConnectionStringBuilder(t);
            return Postgres(b);
        }

        return Sqlite(t);
    }

    private static StoreLocation FromUri(string text)
    {
        if (!Uri.TryCreate(text, UriKind.Absolute, out var uri) || uri.Host.Length == 0)
        {
            throw new FormatException($"{Redact(text)}: expected postgres://user@host[:port]/database");
        }

        var b = new Npgsql.NpgsqlConnectionStringBuilder { Host = uri.Host, Port = uri.IsDefaultPort || uri.Port <= 0 ? 5432 : uri.Port };
        var database = Uri.UnescapeDataString(uri.AbsolutePath.Trim('/'));
        if (database.Length > 0)
        {
            b.Database = database;
        }

        if (uri.UserInfo.Length > 0)
        {
            var colon = uri.UserInfo.IndexOf(':', StringComparison.Ordinal);
            b.Username = Uri.UnescapeDataString(colon < 0 ? uri.UserInfo : uri.UserInfo[..colon]);
            if (colon >= 0)
            {
                b.Password = Uri.UnescapeDataString(uri.UserInfo[(colon + 1)..]);
            }
        }

        return Postgres(b);
    }

    private static StoreLocation Postgres(Npgsql.NpgsqlConnectionStringBuilder b)
    {
        // Statements stay short; a station must notice a lost server within seconds, not minutes.
        if (!b.ContainsKey("Timeout") || b.Timeout == 15)
        {
            b.Timeout = 5;
        }

        var display = $"postgres://{(b.Username is { Length: > 0 } u ? u + "@" : string.Empty)}{b.Host}:{b.Port}/{b.Database}";
        return new StoreLocation(StoreEngine.Postgres, b.ConnectionString, display);
    }

    /// <summary>A URI or connection string with any password replaced by <c>***</c> (for messages about a bad one).</summary>
    public static string Redact(string text)
    {
        ArgumentNullException.ThrowIfNull(text);
        var r = System.Text.RegularExpressions.Regex.Replace(text, @"(://[^:/@]*:)[^@]*@", "$1***@");
        return System.Text.RegularExpressions.Regex.Replace(r, @"(?i)(password|pwd)\s*=\s*[^;]*", "$1=***");
    }

    /// <inheritdoc />
    public override string ToString() => Display;
}
