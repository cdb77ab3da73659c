using System.CommandLine;
using Microsoft.Data.Sqlite;
using PmacStream.Cli;

namespace PmacStream.IntegrationTests;

public class CliTests
{
    [Fact]
    public void Exit_codes_follow_the_convention()
    {
        CliGlobals.Ok.Should().Be(0);
        CliGlobals.Failed.Should().Be(1);
        CliGlobals.UsageOrIo.Should().Be(2);
    }

    [Fact]
    public async Task A_database_error_is_a_usage_or_io_error_and_a_bug_is_not()
    {
        // SQLite's exception is recognised in a method of its own (so that commands without a database do not load
        // the SQLite assemblies): it must still be reported in one line with exit 2, and anything else as a bug.
        static Command Throwing(string name, Exception e)
        {
            var cmd = new Command(name);
            cmd.SetAction(new Func<ParseResult, int>(_ => throw e));
            return cmd;
        }

        var root = new RootCommand { Throwing("locked", new SqliteException("database is locked", 5)), Throwing("bug", new InvalidOperationException("bug")) };
        (await CliGlobals.InvokeAsync(root.Parse(["locked"]))).Should().Be(CliGlobals.UsageOrIo);
        (await CliGlobals.InvokeAsync(root.Parse(["bug"]))).Should().Be(CliGlobals.Failed);
    }
}
