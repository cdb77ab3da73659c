using System.CommandLine;
using PmacStream.Preparation.Store;

namespace PmacStream.Cli.Commands;

/// <summary>
/// <c>--store URI</c> (and, on the job commands, <c>--job-db PATH</c>), shared by every command that reads or writes
/// records: <c>sqlite:PATH</c>, <c>postgres://user@host:port/db</c> or an Npgsql connection string; else
/// <c>$PMACSTREAM_STORE</c>, else <c>~/.pmacstream/store.db</c>.
/// </summary>
internal static class StoreOptions
{
    /// <summary>A fresh <c>--store</c> option (an option belongs to one command).</summary>
    public static Option<string?> Option() => new("--store")
    {
        Description = "The store of programs and jobs: sqlite:PATH, postgres://USER@HOST:PORT/DB or an Npgsql connection string (password from PGPASSWORD/PGPASSFILE or the URI); default $PMACSTREAM_STORE, else ~/.pmacstream/store.db.",
        HelpName = "URI",
    };

    /// <summary>The store named by <paramref name="store"/> or <paramref name="jobDb"/>, else the environment's or the default; a bad location is a usage error.</summary>
    public static StoreLocation Resolve(string? store, string? jobDb = null)
    {
        try
        {
            return StoreLocation.Resolve(store, jobDb);
        }
        catch (Exception e) when (e is FormatException or ArgumentException)
        {
            throw new CliException($"--store {StoreLocation.Redact(store ?? string.Empty)}: {StoreLocation.Redact(e.Message)}");
        }
    }
}
