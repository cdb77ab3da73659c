using System.CommandLine;
using System.Globalization;
using System.Net;
using System.Runtime.InteropServices;
using PmacStream.Pmac;
using PmacStream.Sim;
using PmacStream.Sim.Servers;

namespace PmacStream.Cli.Commands;

/// <summary>`pmacstream sim`: the simulated Turbo PMAC served over Ethernet (VR_PMAC) and/or a serial line.</summary>
internal static class SimCommand
{
    public static Command Create()
    {
        var tcp = new Option<string>("--tcp") { Description = "Serve Ethernet (VR_PMAC packets) on HOST:PORT; port 0 = any free port; 'none' = no Ethernet.", DefaultValueFactory = _ => "127.0.0.1:1025" };
        var serial = new Option<string?>("--serial") { Description = "Also serve the serial ASCII protocol on this tty or pty path (one end of a socat pair)." };
        var baud = new Option<int>("--baud") { Description = "Baud rate set on the --serial line.", DefaultValueFactory = _ => 38400 };
        var speed = new Option<string>("--speed") { Description = "Virtual clock: realtime, Nx (e.g. 50x) or instant.", DefaultValueFactory = _ => "realtime" };
        var rotWords = new Option<int?>("--rot-words") { Description = "Rotary buffer words of C.S. 1 at power-on (default: the simulator's, 65536; 0 = host must DEFINE ROT)." };
        var executedLog = new Option<string?>("--executed-log") { Description = "Write the executed-move log (CSV) here when the simulator stops." };

        var cmd = new Command("sim", "Run the simulated Turbo PMAC as a server until Ctrl-C or SIGTERM.");
        foreach (var o in new Option[] { tcp, serial, baud, speed, rotWords, executedLog })
        {
            cmd.Options.Add(o);
        }

        cmd.SetAction(async (parse, ct) =>
        {
            var options = new SimOptions();
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

            await using var host = new SimHost(new SimHostOptions
            {
                Simulator = options,
                TcpEndPoint = endPoint,
                SerialPath = serialPath,
                Serial = new SerialSettings(parse.GetValue(baud)),
                ExecutedLogPath = parse.GetValue(executedLog),
            });

            // SIGTERM and Ctrl-C both end the wait below; the host then stops and writes the log.
            using var stop = CancellationTokenSource.CreateLinkedTokenSource(ct);
            using var sigterm = PosixSignalRegistration.Create(PosixSignal.SIGTERM, c =>
            {
                c.Cancel = true;
                stop.Cancel();
            });
            using var sigint = PosixSignalRegistration.Create(PosixSignal.SIGINT, c =>
            {
                c.Cancel = true;
                stop.Cancel();
            });
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

    private static IPEndPoint ParseEndPoint(string spec)
    {
        var colon = spec.LastIndexOf(':');
        var host = colon >= 0 ? spec[..colon] : spec;
        var port = 1025;
        if (colon >= 0 && (!int.TryParse(spec.AsSpan(colon + 1), NumberStyles.None, CultureInfo.InvariantCulture, out port) || port > 65535))
        {
            throw new CliException($"--tcp '{spec}': the port must be 0..65535");
        }

        host = host.Trim('[', ']');
        if (host.Length == 0 || host == "localhost")
        {
            host = "127.0.0.1";
        }

        if (!IPAddress.TryParse(host, out var address))
        {
            throw new CliException($"--tcp '{spec}': expected an IP address and port, e.g. 127.0.0.1:1025");
        }

        return new IPEndPoint(address, port);
    }
}
