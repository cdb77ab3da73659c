using System.CommandLine;
using PmacStream.Preparation.Store;

namespace PmacStream.Cli.Commands;

/// <summary>
/// <c>pmacstream store [info|migrate] [--store URI]</c>: where the store is and its schema version; <c>migrate</c>
/// brings it to this version's schema (on PostgreSQL run it as the database's owner: a station's role may not create
/// tables).
/// </summary>
internal static class StoreCommand
{
    public static Command Create()
    {
        var cmd = new Command("store", "The store of programs and jobs: where it is, and its schema (migrate).");
        var store = StoreOptions.Option();
        store.Recursive = true;
        cmd.Options.Add(store);
        Task<int> Run(ParseResult parse, bool migrate, CancellationToken ct) =>
            new StoreHandler().RunAsync(new StoreCommandOptions(StoreOptions.Resolve(parse.GetValue(store)), migrate), CliConsole.Of(parse), ct);
        cmd.SetAction((parse, ct) => Run(parse, false, ct));
        var info = new Command("info", "Print the store's location (never its password) and schema version.");
        info.SetAction((parse, ct) => Run(parse, false, ct));
        cmd.Subcommands.Add(info);
        var migrate = new Command("migrate", "Bring the store's schema to this version (create it when new).");
        migrate.SetAction((parse, ct) => Run(parse, true, ct));
        cmd.Subcommands.Add(migrate);
        return cmd;
    }
}

/// <summary>What a <c>store</c> command line asks for.</summary>
/// <param name="Store">The store.</param>
/// <param name="Migrate">Bring its schema to this version (<c>store migrate</c>) rather than describe it.</param>
internal sealed record StoreCommandOptions(StoreLocation Store, bool Migrate);

/// <summary><c>pmacstream store</c>: the store's location and schema version; <c>migrate</c> brings the schema up to date.</summary>
internal sealed class StoreHandler
{
    /// <summary>Describes or migrates the store; returns the exit code.</summary>
    public Task<int> RunAsync(StoreCommandOptions options, CliConsole console, CancellationToken ct) =>
        Task.FromResult(options.Migrate ? Migrate(options.Store, console.Out) : Info(options.Store, console.Out));

    private static int Info(StoreLocation location, TextWriter output)
    {
        using (ProgramsCommand.OpenStore(location))
        {
        }

        output.WriteLine($"store {location.Display} ({location.Engine.ToString().ToLowerInvariant()}), schema version {SqliteMigrations.Latest}");
        return CliGlobals.Ok;
    }

    private static int Migrate(StoreLocation location, TextWriter output)
    {
        // Opening migrates (both engines); the programs' side opens every table.
        using (ProgramsCommand.OpenStore(location))
        {
        }

        output.WriteLine($"store {location.Display}: schema at version {SqliteMigrations.Latest}");
        return CliGlobals.Ok;
    }
}
