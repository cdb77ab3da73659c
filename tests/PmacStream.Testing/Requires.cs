namespace PmacStream.Testing;

/// <summary>
/// What a test needs from the machine. When it is missing the test reports SKIPPED with the reason (the test must be
/// a <c>[SkippableFact]</c> or <c>[SkippableTheory]</c>), never PASSED; <c>.ci/run</c> installs everything and fails
/// on any skip. When the resource is there but broken, the test fails.
/// </summary>
public static class Requires
{
    /// <summary>
    /// A PostgreSQL server for the store's tests: <c>PMACSTREAM_TEST_PG</c> (an Npgsql connection string of a station's
    /// role) and, to create or migrate the schema first, <c>PMACSTREAM_TEST_PG_ADMIN</c> (the database owner's).
    /// .ci/run starts a throwaway cluster and sets both (scripts/pg-throwaway.sh).
    /// </summary>
    public static (string Station, string? Admin) Postgres()
    {
        var station = Environment.GetEnvironmentVariable("PMACSTREAM_TEST_PG");
        Skip.If(string.IsNullOrEmpty(station),
            "PMACSTREAM_TEST_PG is not set: no PostgreSQL server for the store's tests (scripts/pg-throwaway.sh start DIR prints it; .ci/run starts one)");
        var admin = Environment.GetEnvironmentVariable("PMACSTREAM_TEST_PG_ADMIN");
        return (station!, string.IsNullOrEmpty(admin) ? null : admin);
    }

    /// <summary>socat on PATH (it makes the pty pair the serial tests talk through); returns its full path.</summary>
    public static string Socat()
    {
        NotWindows("a pty pair");
        var socat = Tools.Find("socat");
        Skip.If(socat is null, "socat is not on PATH: no pty pair for the serial tests (apt-get install socat; .ci/run installs it)");
        return socat!;
    }

    /// <summary>LinuxCNC's stand-alone interpreter <c>rs274</c> (Debian package linuxcnc-uspace); returns its full path.</summary>
    public static string Rs274()
    {
        NotWindows("LinuxCNC's rs274");
        var rs274 = Tools.Find("rs274") ?? (File.Exists("/usr/bin/rs274") ? "/usr/bin/rs274" : null);
        Skip.If(rs274 is null, "rs274 is not on PATH: no independent interpreter to compare with (apt-get install linuxcnc-uspace; .ci/run installs it)");
        return rs274!;
    }

    /// <summary>
    /// The PComm32 stand-in library that the build makes with gcc. Skipped when gcc is not on PATH; when gcc is
    /// there and the library is not, the build broke and the test fails.
    /// </summary>
    public static string PComm32StandIn()
    {
        NotWindows("the stand-in is a Linux shared library");
        var path = System.IO.Path.Combine(AppContext.BaseDirectory, "libpcomm32standin.so");
        if (File.Exists(path))
        {
            return path;
        }

        Skip.If(Tools.Find("gcc") is null, "gcc is not on PATH: the PComm32 stand-in library was not built (apt-get install gcc; .ci/run installs it)");
        throw new InvalidOperationException($"gcc is on PATH but the build left no {path}: see the BuildPComm32StandIn step of the build output");
    }

    /// <summary>The shared CAM corpus's programs (<c>../shared/gcode-corpus</c>), in name order.</summary>
    public static IReadOnlyList<string> Corpus()
    {
        var files = RepoRoot.CorpusPrograms;
        Skip.If(files is null, $"the shared CAM corpus {System.IO.Path.GetFullPath(System.IO.Path.Combine(RepoRoot.Path, "..", "shared", "gcode-corpus"))} is absent");
        return files!;
    }

    /// <summary>A POSIX system (ptys, shared libraries built with gcc).</summary>
    public static void NotWindows(string why) => Skip.If(OperatingSystem.IsWindows(), $"needs Linux or macOS: {why}");
}
