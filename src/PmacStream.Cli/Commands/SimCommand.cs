using System.CommandLine;
using System.Globalization;
using System.Net;
using System.Runtime.InteropServices;
using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Sim.Servers;

namespace PmacStream.Cli.Commands;

/// <summary>The options of <c>pmacstream sim</c>, bound.</summary>
/// <param name="Tcp">HOST:PORT, PORT or <c>none</c>.</param>
/// <param name="Serial">The tty or pty served besides, or null.</param>
/// <param name="Baud">Baud rate of the serial line.</param>
/// <param name="Speed">Virtual clock: realtime, Nx or instant.</param>
/// <param name="RotWords">Rotary buffer words at power-on, null: the simulator's.</param>
/// <param name="ExecutedLog">The executed-move log's file, or null.</param>
/// <param name="IdleTimeout">Seconds without a packet before an Ethernet connection closes (0: never).</param>
/// <param name="MaxClients">Ethernet connections served at once.</param>
/// <param name="Library">The library loaded at start: a profile, a library file or <c>none</c>.</param>
/// <param name="Homed">Start with every motor homed (<c>--homed</c>); else unhomed, as incremental encoders start.</param>
/// <param name="Inject">Faults to inject, <c>KIND:MOTOR@SECONDS</c> each.</param>
/// <param name="Travel">Hardware overtravel limit switches at +-this many counts from each motor's power-on position (0: none).</param>
internal sealed record SimArgs(string Tcp, string? Serial, int Baud, string Speed, int? RotWords, string? ExecutedLog, double IdleTimeout, int MaxClients, string Library,
    bool Homed = false, IReadOnlyList<string>? Inject = null, double Travel = 0);

/// <summary>`pmacstream sim`: the simulated Turbo PMAC served over Ethernet (VR_PMAC) and/or a serial line.</summary>
internal static class SimCommand
{
    public static Command Create()
    {
        var tcp = new Option<string>("--tcp") { Description = "Serve Ethernet (VR_PMAC packets) on HOST:PORT, or PORT alone (on 127.0.0.1); port 0 = any free port; 'none' = no Ethernet. A PMAC port has no authentication: anything but loopback is reachable by every host that can route to it.", DefaultValueFactory = _ => "127.0.0.1:1025" };
        var serial = new Option<string?>("--serial") { Description = "Also serve the serial ASCII protocol on this tty or pty path (one end of a socat pair)." };
        var baud = new Option<int>("--baud") { Description = "Baud rate set on the --serial line.", DefaultValueFactory = _ => 38400 };
        var speed = new Option<string>("--speed") { Description = "Virtual clock: realtime, Nx (e.g. 50x) or instant.", DefaultValueFactory = _ => "realtime" };
        var rotWords = new Option<int?>("--rot-words") { Description = "Rotary buffer words of C.S. 1 at power-on (default: the simulator's, 65536; 0 = host must DEFINE ROT)." };
        var executedLog = new Option<string?>("--executed-log") { Description = "Write the executed-move log (CSV) here: streamed to FILE.tmp as moves run, moved to FILE when the simulator stops." };
        var idleTimeout = new Option<double>("--idle-timeout") { Description = "Close an Ethernet connection after this many seconds without a packet (0 = never).", DefaultValueFactory = _ => 300 };
        var maxClients = new Option<int>("--max-clients") { Description = "Ethernet connections served at once; when all are taken, the one idle longest (2 s or more) makes room for a new client.", DefaultValueFactory = _ => 32 };

        var homed = new Option<bool>("--homed") { Description = "Start with every motor homed (Home Complete set), as a machine with absolute encoders. Without it the simulator starts unhomed, as a machine with incremental encoders does: home with #nHM." };
        var inject = new Option<string[]>("--inject")
        {
            Description = "Inject a fault KIND:MOTOR@SECONDS, SECONDS on the simulator's clock after a motion program first starts running (homing and jogging do not count). KIND: limit+, limit- (stays until the motor is jogged off it), fatal-following-error, amp-fault (until re-enabled: #nJ/, #n$ or &nA). Repeatable.",
            HelpName = "KIND:MOTOR@SECONDS",
            AllowMultipleArgumentsPerToken = false,
        };
        // A machine has ends of travel: without them a homing search started past the home switch (which captures on
        // the flag's edge) or a runaway jog would never stop.
        var travel = new Option<double>("--travel")
        {
            Description = "Hardware overtravel limit switches of every motor at +-this many counts (mm at the power-on scale) from where it stood at power-on; 0 = none. A motor that reaches one stops there (Stopped on Position Limit) until jogged off it.",
            HelpName = "COUNTS",
            DefaultValueFactory = _ => 100_000,
        };
        var library = new Option<string>("--library")
        {
            Description = "The PROG 1000/1001 library loaded at start, as on a configured controller: a profile (built-in name or JSON file) whose library and tables are loaded, a PMAC library file (e.g. from 'pmacstream prog1000'), or 'none' (a bare controller).",
            HelpName = "NAME|FILE|none",
            DefaultValueFactory = _ => MachineProfile.DefaultName,
        };
        var cmd = new Command("sim", "Run the simulated Turbo PMAC as a server until Ctrl-C or SIGTERM.");
        foreach (var o in new Option[] { tcp, serial, baud, speed, rotWords, executedLog, idleTimeout, maxClients, library, homed, inject, travel })
        {
            cmd.Options.Add(o);
        }

        cmd.SetAction((parse, ct) => RunAsync(
            new SimArgs(parse.GetValue(tcp)!, parse.GetValue(serial), parse.GetValue(baud), parse.GetValue(speed)!, parse.GetValue(rotWords), parse.GetValue(executedLog),
                parse.GetValue(idleTimeout), parse.GetValue(maxClients), parse.GetValue(library)!, parse.GetValue(homed), parse.GetValue(inject) ?? [], parse.GetValue(travel)),
            CliConsole.Of(parse),
            ct));
        return cmd;
    }

    /// <summary>Serves the simulator until Ctrl-C, SIGTERM or <paramref name="ct"/>; returns the exit code.</summary>
    /// <exception cref="CliException">An option is out of range, or the port cannot be served.</exception>
    internal static async Task<int> RunAsync(SimArgs args, CliConsole console, CancellationToken ct)
    {
        var hostOptions = HostOptions(args);
        await using var host = new SimHost(hostOptions);
        var libraryLines = LibraryLines(args.Library);
        if (libraryLines.Count > 0)
        {
            await new InProcessConnection(host.Simulator.OpenPort("library"), "library").DownloadAsync(libraryLines, ct).ConfigureAwait(false);
        }

        if (hostOptions.TcpEndPoint is { } endPoint && SimHost.IsExposed(endPoint))
        {
            await console.Error.WriteLineAsync($"pmacstream sim: warning: {endPoint} is reachable from other machines and a PMAC port has no authentication: anyone who can connect can run motion programs. Serve 127.0.0.1 unless the network is isolated.").ConfigureAwait(false);
        }

        // SIGTERM and Ctrl-C end the wait below; the host then stops and moves the executed-move log into place.
        // The command line cancels the token too, but only once this action has returned its task, which is after
        // "listening" is printed: a script that signals as soon as it reads that line would find no handler yet.
        // Both handlers run; this one may come after the token is gone.
        using var stop = CancellationTokenSource.CreateLinkedTokenSource(ct);
        void OnSignal(PosixSignalContext c)
        {
            c.Cancel = true;
            try
            {
                stop.Cancel();
            }
            catch (ObjectDisposedException)
            {
                // Already stopped by the other handler and disposed: nothing left to do.
            }
        }

        using var sigterm = PosixSignalRegistration.Create(PosixSignal.SIGTERM, OnSignal);
        using var sigint = PosixSignalRegistration.Create(PosixSignal.SIGINT, OnSignal);
        try
        {
            await ServeAsync(host, hostOptions, console, stop.Token).ConfigureAwait(false);
        }
        finally
        {
            var counters = await host.StopAsync().ConfigureAwait(false);
            await console.Out.WriteLineAsync(string.Create(CultureInfo.InvariantCulture, $"pmacstream sim: stopped ({counters.MovesExecuted} moves, {counters.Underruns} underruns, {counters.Errors} errors)")).ConfigureAwait(false);
        }

        return CliGlobals.Ok;
    }

    /// <summary>
    /// The host's options from the bound ones (the executed-move log is streamed to its file: memory does not grow with
    /// the program). A served controller starts unhomed, as a machine with incremental encoders, unless --homed. The
    /// simulated machine is the profile's: its rapids at the profile's rapid rate (the motors' Ixx16/Ixx22 on a real one),
    /// so the host's move times and the ETA agree with it.
    /// </summary>
    private static SimHostOptions HostOptions(SimArgs args)
    {
        var options = new SimOptions { RetainExecutedMoves = false, StartHomed = args.Homed, RapidFeed = RapidRate(args.Library) };
        if (args.Travel < 0 || double.IsNaN(args.Travel))
        {
            throw new CliException($"--travel {args.Travel}: expected 0 (none) or a positive number of counts");
        }

        for (var m = 1; args.Travel > 0 && m <= SimOptions.MotorCount; m++)
        {
            options.MotorSettings[m] = new MotorSettings { PlusLimitPosition = args.Travel, MinusLimitPosition = -args.Travel };
        }

        foreach (var spec in args.Inject ?? [])
        {
            try
            {
                options.Faults.Add(FaultInjection.Parse(spec));
            }
            catch (FormatException e)
            {
                throw new CliException(e.Message);
            }
        }

        try
        {
            options.Speed = SimSpeed.Parse(args.Speed);
        }
        catch (FormatException e)
        {
            throw new CliException(e.Message);
        }

        if (args.RotWords is { } words)
        {
            options.DefaultRotWords = words >= 0 ? words : throw new CliException("--rot-words must be 0 or more");
        }

        var endPoint = args.Tcp.Equals("none", StringComparison.OrdinalIgnoreCase) ? null : ParseEndPoint(args.Tcp);
        if (endPoint is null && args.Serial is null)
        {
            throw new CliException("nothing to serve: give --tcp HOST:PORT and/or --serial PATH");
        }

        if (!(args.IdleTimeout >= 0) || args.MaxClients < 1)
        {
            throw new CliException("--idle-timeout must be 0 or more seconds and --max-clients 1 or more");
        }

        return new SimHostOptions
        {
            Simulator = options,
            TcpEndPoint = endPoint,
            SerialPath = args.Serial,
            Serial = new SerialSettings(args.Baud),
            ExecutedLogPath = args.ExecutedLog,
            TcpServer = new PmacTcpServerOptions
            {
                IdleTimeout = args.IdleTimeout == 0 ? Timeout.InfiniteTimeSpan : TimeSpan.FromSeconds(args.IdleTimeout),
                MaxClients = args.MaxClients,
            },
        };
    }

    /// <summary>Starts the host, says where it listens, and waits for <paramref name="stop"/>.</summary>
    private static async Task ServeAsync(SimHost host, SimHostOptions options, CliConsole console, CancellationToken stop)
    {
        try
        {
            host.Start();
        }
        catch (System.Net.Sockets.SocketException e)
        {
            throw new CliException($"cannot listen on {options.TcpEndPoint}: {e.Message}");
        }
        catch (Exception e) when (e is IOException or UnauthorizedAccessException)
        {
            throw new CliException(e.Message);
        }

        var speed = options.Simulator.Speed;
        if (host.TcpEndPoint is { } bound)
        {
            await console.Out.WriteLineAsync(string.Create(CultureInfo.InvariantCulture, $"pmacstream sim: listening on tcp {bound} (port {bound.Port}), speed {speed}")).ConfigureAwait(false);
        }

        if (options.SerialPath is not null)
        {
            await console.Out.WriteLineAsync($"pmacstream sim: serving serial {options.SerialPath}, speed {speed}").ConfigureAwait(false);
        }

        await console.Out.WriteLineAsync(options.Simulator.StartHomed ? "pmacstream sim: motors homed at start (--homed)" : "pmacstream sim: motors not homed at start (home with #nHM, or start with --homed)").ConfigureAwait(false);
        foreach (var fault in options.Simulator.Faults)
        {
            await console.Out.WriteLineAsync(string.Create(CultureInfo.InvariantCulture, $"pmacstream sim: will inject {fault} ({fault.Seconds} s after a motion program first starts)")).ConfigureAwait(false);
        }

        console.Out.Flush();
        try
        {
            await Task.Delay(Timeout.Infinite, stop).ConfigureAwait(false);
        }
        catch (OperationCanceledException)
        {
            // Ctrl-C or SIGTERM: a clean stop.
        }
    }

    /// <summary>
    /// <c>HOST:PORT</c>, <c>[V6]:PORT</c>, <c>HOST</c> (port 1025) or <c>PORT</c> alone (127.0.0.1); <c>localhost</c> and
    /// an empty host are 127.0.0.1. Only dotted IPv4 or IPv6 addresses: a bare number is a port, never an address.
    /// </summary>
    internal static IPEndPoint ParseEndPoint(string spec)
    {
        if (spec.Length > 0 && spec.All(char.IsAsciiDigit))
        {
            return new IPEndPoint(IPAddress.Loopback, ParsePort(spec, spec));
        }

        var bracket = spec.StartsWith('[') ? spec.IndexOf(']', StringComparison.Ordinal) : -1;
        var colon = spec.LastIndexOf(':');
        var hasPort = bracket >= 0 ? colon > bracket : colon >= 0 && spec.IndexOf(':') == colon;
        var host = hasPort ? spec[..colon] : spec;
        var port = hasPort ? ParsePort(spec[(colon + 1)..], spec) : 1025;
        host = host.Trim('[', ']');
        if (host.Length == 0 || host.Equals("localhost", StringComparison.OrdinalIgnoreCase))
        {
            host = "127.0.0.1";
        }

        // IPAddress.TryParse takes "44887" or "1.2" as IPv4 numbers; only the dotted quad or IPv6 is an address here.
        var dotted = host.Count(c => c == '.') == 3 && host.All(c => char.IsAsciiDigit(c) || c == '.');
        if (!(dotted || host.Contains(':')) || !IPAddress.TryParse(host, out var address))
        {
            throw new CliException($"--tcp '{spec}': expected PORT, HOST:PORT or [IPv6]:PORT with an IP address, e.g. 1025 or 127.0.0.1:1025");
        }

        return new IPEndPoint(address, port);
    }

    private static int ParsePort(string text, string spec) =>
        int.TryParse(text, NumberStyles.None, CultureInfo.InvariantCulture, out var port) && port <= 65535
            ? port
            : throw new CliException($"--tcp '{spec}': the port must be 0..65535");

    /// <summary>The rapid rate of the machine <c>--library</c> names: a profile's, else the default profile's.</summary>
    private static double RapidRate(string choice) =>
        string.Equals(choice, "none", StringComparison.OrdinalIgnoreCase) || (MachineProfile.Named(choice) is null && !choice.EndsWith(".json", StringComparison.OrdinalIgnoreCase))
            ? MachineProfile.Default.RapidRate
            : CliProfiles.Load(choice).RapidRate;

    /// <summary>What <c>--library</c> loads: a profile's library and tables, a library file's statements, or nothing.</summary>
    private static IReadOnlyList<string> LibraryLines(string choice)
    {
        if (string.Equals(choice, "none", StringComparison.OrdinalIgnoreCase))
        {
            return [];
        }

        if (MachineProfile.Named(choice) is null && File.Exists(choice) && !choice.EndsWith(".json", StringComparison.OrdinalIgnoreCase))
        {
            return File.ReadAllLines(choice).Select(l => l.Trim()).Where(l => l.Length > 0 && l[0] != ';').ToList();
        }

        var profile = CliProfiles.Load(choice);
        return [.. ControllerLibrary.Lines(profile), .. ControllerLibrary.TableLines(profile)];
    }
}
