using System.CommandLine;
using PmacStream.Preparation.Store;

namespace PmacStream.Cli.Commands;

/// <summary>
/// <c>--store URI</c> (and, on the job commands, <c>--job-db PATH</c>), shared by every command that reads or writes
/// records: <c>sqlite:PATH</c>, <c>postgres://user@host:port/db</c> or an Npgsql connection string; else
/// the settings file's <c>store</c>, else <c>$PMACSTREAM_STORE</c>, else <c>~/.pmacstream/store.db</c>.
/// </summary>
internal static class StoreOptions
{
    /// <summary>A fresh <c>--store</c> option (an option belongs to one command).</summary>
    public static Option<string?> Option() => new("--store")
    {
        Description = "The store of programs and jobs: sqlite:PATH, postgres://USER@HOST:PORT/DB or an Npgsql connection string (password from PGPASSWORD/PGPASSFILE or the URI); default the settings file's store, else $PMACSTREAM_STORE, else ~/.pmacstream/store.db.",
        HelpName = "URI",
    };

    /// <summary>
    /// The store: <paramref name="store"/> (<c>--store</c>), else <paramref name="jobDb"/> (<c>--job-db</c>), else the
    /// settings file's <c>store</c> (<paramref name="settingsPath"/>, or the default file), else <c>$PMACSTREAM_STORE</c>,
    /// else the default file; a bad location is a usage error (its password never shown).
    /// </summary>
    public static StoreLocation Resolve(string? store, string? jobDb = null, string? settingsPath = null)
    {
        string? fromSettings = null;
        if (store is not { Length: > 0 } && jobDb is not { Length: > 0 })
        {
            try
            {
                fromSettings = Jobs.StationSettings.Load(settingsPath).Store;
            }
            catch (Exception e) when (e is Jobs.RunSettingsException or IOException)
            {
                throw new CliException(StoreLocation.Redact(e.Message));
            }
        }

        try
        {
            return StoreLocation.Resolve(store, jobDb, fromSettings);
        }
        catch (Exception e) when (e is FormatException or ArgumentException)
        {
            var named = store is { Length: > 0 } ? "--store " + StoreLocation.Redact(store) : fromSettings is not null ? "the settings file's store" : "$" + StoreLocation.EnvironmentVariable;
            throw new CliException($"{named}: {StoreLocation.Redact(e.Message)}");
        }
    }
}
