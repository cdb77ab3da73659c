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
        cmd.SetAction(parse => Info(StoreOptions.Resolve(parse.GetValue(store))));
        var info = new Command("info", "Print the store's location (never its password) and schema version.");
        info.SetAction(parse => Info(StoreOptions.Resolve(parse.GetValue(store))));
        cmd.Subcommands.Add(info);
        var migrate = new Command("migrate", "Bring the store's schema to this version (create it when new).");
        migrate.SetAction(parse => Migrate(StoreOptions.Resolve(parse.GetValue(store))));
        cmd.Subcommands.Add(migrate);
        return cmd;
    }

    private static int Info(StoreLocation location)
    {
        using (ProgramsCommand.OpenStore(location))
        {
        }

        Console.Out.WriteLine($"store {location.Display} ({location.Engine.ToString().ToLowerInvariant()}), schema version {SqliteMigrations.Latest}");
        return CliGlobals.Ok;
    }

    private static int Migrate(StoreLocation location)
    {
        // Opening migrates (both engines); the programs' side opens every table.
        using (ProgramsCommand.OpenStore(location))
        {
        }

        Console.Out.WriteLine($"store {location.Display}: schema at version {SqliteMigrations.Latest}");
        return CliGlobals.Ok;
    }
}
