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

        var library = new Option<string>("--library")
        {
            Description = "The PROG 1000/1001 library loaded at start, as on a configured controller: a profile (built-in name or JSON file) whose library and tables are loaded, a PMAC library file (e.g. from 'pmacstream prog1000'), or 'none' (a bare controller).",
            HelpName = "NAME|FILE|none",
            DefaultValueFactory = _ => MachineProfile.DefaultName,
        };
        var cmd = new Command("sim", "Run the simulated Turbo PMAC as a server until Ctrl-C or SIGTERM.");
        foreach (var o in new Option[] { tcp, serial, baud, speed, rotWords, executedLog, idleTimeout, maxClients, library })
        {
            cmd.Options.Add(o);
        }

        cmd.SetAction(async (parse, ct) =>
        {
            // The executed-move log is streamed to its file (or not kept): memory does not grow with the program.
            // The simulated machine is the profile's: its rapids at the profile's rapid rate (the motors' Ixx16/Ixx22 on a
            // real one), so the host's move times and the ETA agree with it (issue 28).
            var options = new SimOptions { RetainExecutedMoves = false, RapidFeed = RapidRate(parse.GetValue(library)!) };
            try
            {
                options.Speed = SimSpeed.Parse(parse.GetValue(speed)!);
            }
            catch (FormatException e)
            {
                throw new CliException(e.Message);
            }

            if (parse.GetValue(rotWords) is { } words)
            {
                options.DefaultRotWords = words >= 0 ? words : throw new CliException("--rot-words must be 0 or more");
            }

            var tcpSpec = parse.GetValue(tcp)!;
            var serialPath = parse.GetValue(serial);
            var endPoint = tcpSpec.Equals("none", StringComparison.OrdinalIgnoreCase) ? null : ParseEndPoint(tcpSpec);
            if (endPoint is null && serialPath is null)
            {
                throw new CliException("nothing to serve: give --tcp HOST:PORT and/or --serial PATH");
            }

            var idle = parse.GetValue(idleTimeout);
            var slots = parse.GetValue(maxClients);
            if (!(idle >= 0) || slots < 1)
            {
                throw new CliException("--idle-timeout must be 0 or more seconds and --max-clients 1 or more");
            }

            await using var host = new SimHost(new SimHostOptions
            {
                Simulator = options,
                TcpEndPoint = endPoint,
                SerialPath = serialPath,
                Serial = new SerialSettings(parse.GetValue(baud)),
                ExecutedLogPath = parse.GetValue(executedLog),
                TcpServer = new PmacTcpServerOptions
                {
                    IdleTimeout = idle == 0 ? Timeout.InfiniteTimeSpan : TimeSpan.FromSeconds(idle),
                    MaxClients = slots,
                },
            });
            var libraryLines = LibraryLines(parse.GetValue(library)!);
            if (libraryLines.Count > 0)
            {
                await new InProcessConnection(host.Simulator.OpenPort("library"), "library").DownloadAsync(libraryLines, ct).ConfigureAwait(false);
            }

            if (endPoint is not null && SimHost.IsExposed(endPoint))
            {
                Console.Error.WriteLine($"pmacstream sim: warning: {endPoint} is reachable from other machines and a PMAC port has no authentication: anyone who can connect can run motion programs. Serve 127.0.0.1 unless the network is isolated.");
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
                try
                {
                    host.Start();
                }
                catch (System.Net.Sockets.SocketException e)
                {
                    throw new CliException($"cannot listen on {endPoint}: {e.Message}");
                }
                catch (Exception e) when (e is IOException or UnauthorizedAccessException)
                {
                    throw new CliException(e.Message);
                }

                if (host.TcpEndPoint is { } bound)
                {
                    Console.Out.WriteLine(string.Create(CultureInfo.InvariantCulture, $"pmacstream sim: listening on tcp {bound} (port {bound.Port}), speed {options.Speed}"));
                }

                if (serialPath is not null)
                {
                    Console.Out.WriteLine($"pmacstream sim: serving serial {serialPath}, speed {options.Speed}");
                }

                Console.Out.Flush();
                try
                {
                    await Task.Delay(Timeout.Infinite, stop.Token).ConfigureAwait(false);
                }
                catch (OperationCanceledException)
                {
                    // Ctrl-C or SIGTERM: a clean stop.
                }
            }
            finally
            {
                var counters = await host.StopAsync().ConfigureAwait(false);
                Console.Out.WriteLine(string.Create(CultureInfo.InvariantCulture, $"pmacstream sim: stopped ({counters.MovesExecuted} moves, {counters.Underruns} underruns, {counters.Errors} errors)"));
            }

            return CliGlobals.Ok;
        });
        return cmd;
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
