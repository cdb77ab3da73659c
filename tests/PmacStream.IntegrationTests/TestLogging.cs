using System.Runtime.CompilerServices;

namespace PmacStream.IntegrationTests;

/// <summary>Sets up the log before any test runs: what a command run in process logs reaches its capture.</summary>
internal static class TestLogging
{
    // A module initializer, not a fixture: a logger a type takes from Serilog's silent default when it is first used
    // stays silent, so the capturing one must be in place before any test touches a logging type.
#pragma warning disable CA2255 // a test assembly's own start-up, not a library's
    [ModuleInitializer]
    internal static void Install() => LogCapture.Install();
#pragma warning restore CA2255
}
