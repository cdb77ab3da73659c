using System.CommandLine;
using System.Globalization;
using PmacStream.Jobs;
using Serilog;
using Serilog.Events;

namespace PmacStream.Cli;

/// <summary>Options every command shares, logging set-up, and the exit-code convention.</summary>
internal static class CliGlobals
{
    /// <summary>Success.</summary>
    public const int Ok = 0;

    /// <summary>The input has errors or the job failed.</summary>
    public const int Failed = 1;

    /// <summary>Usage or I/O error.</summary>
    public const int UsageOrIo = 2;

    /// <summary>How long a command may take to stop cleanly after Ctrl-C or SIGTERM before the process is ended.</summary>
    public static readonly TimeSpan TerminationGrace = TimeSpan.FromSeconds(30);

    public static readonly Option<bool> Verbose = new("--verbose", "-v")
    {
        Description = "Log every controller command and reply (Debug level) to stderr.",
        Recursive = true,
    };

    public static readonly Option<string?> LogFile = new("--log-file")
    {
        Description = "Also write the log (Debug level) to this file.",
        Recursive = true,
    };

    public static async Task<int> RunAsync(RootCommand root, string[] args)
    {
        var parse = root.Parse(args);
        ConfigureLogging(parse.GetValue(Verbose), parse.GetValue(LogFile));
        try
        {
            return await InvokeAsync(parse, CliConsole.Standard, TerminationGrace, CancellationToken.None).ConfigureAwait(false);
        }
        finally
        {
            await Log.CloseAndFlushAsync().ConfigureAwait(false);
        }
    }

    /// <summary>
    /// Runs a parsed command line with the exit-code convention: every command's one-line errors, I/O errors and
    /// bugs are turned into a message and a code here, once. Leaves logging alone, so tests can call it in process.
    /// </summary>
    public static Task<int> InvokeAsync(ParseResult parse) => InvokeAsync(parse, CliConsole.Standard, TerminationGrace, CancellationToken.None);

    /// <summary>
    /// Runs a parsed command line writing to <paramref name="console"/>, with the exit-code convention. Ctrl-C and
    /// SIGTERM cancel the command when <paramref name="terminationGrace"/> is given (the process); in a test's
    /// process nothing is hooked and <paramref name="ct"/> stops the command.
    /// </summary>
    public static async Task<int> InvokeAsync(ParseResult parse, CliConsole console, TimeSpan? terminationGrace, CancellationToken ct)
    {
        var prefix = parse.CommandResult.Command is RootCommand ? "pmacstream" : $"pmacstream {parse.CommandResult.Command.Name}";
        if (parse.Errors.Count > 0)
        {
            foreach (var e in parse.Errors)
            {
                await console.Error.WriteLineAsync($"{prefix}: {e.Message}").ConfigureAwait(false);
            }

            await console.Error.WriteLineAsync("Try 'pmacstream --help'.").ConfigureAwait(false);
            return UsageOrIo;
        }

        try
        {
            // System.CommandLine's own handler would print a stack trace and exit 1 for these. Ctrl-C and SIGTERM cancel
            // the command's token (2.0.0 leaves that off unless a timeout is given): a split removes its work folder,
            // a stream stops sending and leaves the job resumable, a check stops. After the timeout the process ends.
            var configuration = console.Configure(new InvocationConfiguration { EnableDefaultExceptionHandler = false, ProcessTerminationTimeout = terminationGrace });
            return await parse.InvokeAsync(configuration, ct).ConfigureAwait(false);
        }
        catch (CliException e)
        {
            await console.Error.WriteLineAsync($"{prefix}: {e.Message}").ConfigureAwait(false);
            return e.ExitCode;
        }
        catch (RunSettingsException e)
        {
            // Already FILE:LINE:COL: error CODE: message, as every bad input is reported.
            await console.Error.WriteLineAsync(e.Message).ConfigureAwait(false);
            return UsageOrIo;
        }
        catch (ProgramRefusedException e)
        {
            Refusals.Print(console.Error, prefix, parse.CommandResult.Command.Name, e);
            return Failed;
        }
        catch (PmacStream.Streaming.JobStoreException e)
        {
            // Names the file and what is wrong (a damaged database is already moved aside); no stack trace.
            await console.Error.WriteLineAsync($"{prefix}: {e.Message}").ConfigureAwait(false);
            return UsageOrIo;
        }
        catch (JobException e)
        {
            await console.Error.WriteLineAsync($"{prefix}: {e.Message}").ConfigureAwait(false);
            return e.Kind == JobErrorKind.BadRequest ? UsageOrIo : Failed;
        }
        catch (Exception e) when (e is IOException or InvalidDataException or UnauthorizedAccessException || IsSqliteError(e))
        {
            await console.Error.WriteLineAsync($"{prefix}: {e.Message}").ConfigureAwait(false);
            return UsageOrIo;
        }
        catch (Exception e) when (StoreError(e) is { } message)
        {
            // The shop's PostgreSQL failed or did not answer in time: what the server said, not a stack trace.
            await console.Error.WriteLineAsync($"{prefix}: the store: {message}").ConfigureAwait(false);
            return Failed;
        }
        catch (OperationCanceledException)
        {
            await console.Error.WriteLineAsync($"{prefix}: interrupted").ConfigureAwait(false);
            return Failed;
        }
        catch (Exception e)
        {
            // A bug, not bad input: one line for the operator, the stack trace in the log file.
            Log.Fatal(e, "unexpected error");
            await console.Error.WriteLineAsync($"{prefix}: unexpected error: {e.Message} (run with --log-file for details)").ConfigureAwait(false);
            return Failed;
        }
    }

    /// <summary>Whether <paramref name="e"/> is SQLite's. A method of its own, never inlined: naming the type in
    /// <see cref="InvokeAsync(ParseResult, CliConsole, TimeSpan?, CancellationToken)"/>'s filter loaded Microsoft.Data.Sqlite and System.Data.Common (about 1.2 MB of the
    /// peak) into every command when it was compiled, even a check or split that never opens a database.</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.NoInlining)]
    private static bool IsSqliteError(Exception e) => e is Microsoft.Data.Sqlite.SqliteException;

    /// <summary>What went wrong with PostgreSQL, in one line; null when <paramref name="e"/> is not Npgsql's. Never
    /// inlined, for the reason <see cref="IsSqliteError"/> gives.</summary>
    [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.NoInlining)]
    private static string? StoreError(Exception e) => e switch
    {
        Npgsql.NpgsqlException { InnerException: TimeoutException t } => $"no answer in time ({t.Message}); a longer 'Command Timeout' in the connection string gives it more",
        Npgsql.NpgsqlException n => n.Message,
        _ => null,
    };

    /// <summary>An input file that exists, or a one-line error (exit 2) that says what is there instead.</summary>
    public static void RequireFile(string path, string expected)
    {
        if (Directory.Exists(path))
        {
            throw new CliException($"{path}: is a directory, expected {expected}");
        }

        if (!File.Exists(path))
        {
            throw new CliException($"{path}: no such file");
        }
    }

    /// <summary>The culture of a <c>--lang</c> value: en or zh-CN (and their usual spellings).</summary>
    public static CultureInfo ParseLanguage(string lang) => lang.ToLowerInvariant() switch
    {
        "en" or "en-us" or "en-gb" => CultureInfo.GetCultureInfo("en"),
        "zh" or "zh-cn" or "zh-hans" => CultureInfo.GetCultureInfo("zh-CN"),
        _ => throw new CliException($"--lang {lang}: expected en or zh-CN"),
    };

    private static void ConfigureLogging(bool verbose, string? logFile)
    {
        var config = new LoggerConfiguration()
            .MinimumLevel.Debug()
            .WriteTo.Console(
                restrictedToMinimumLevel: verbose ? LogEventLevel.Debug : LogEventLevel.Warning,
                standardErrorFromLevel: LogEventLevel.Verbose,
                outputTemplate: "[{Timestamp:HH:mm:ss.fff} {Level:u3}] {Message:lj}{NewLine}{Exception}");
        if (!string.IsNullOrEmpty(logFile))
        {
            config = config.WriteTo.File(logFile, outputTemplate: "{Timestamp:O} [{Level:u3}] {SourceContext} {Message:lj}{NewLine}{Exception}");
        }

        Log.Logger = config.CreateLogger();
    }
}

/// <summary>An error the CLI reports in one line, with its exit code (no stack trace).</summary>
internal sealed class CliException(string message, int exitCode = CliGlobals.UsageOrIo) : Exception(message)
{
    public int ExitCode { get; } = exitCode;
}
