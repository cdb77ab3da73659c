using System.CommandLine;
using System.Globalization;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Cli.Commands;

/// <summary>Which command the job options are for (each takes the options that make sense for it).</summary>
internal enum JobFace
{
    /// <summary><c>stream</c>: a program, a controller, every run setting.</summary>
    Stream,

    /// <summary><c>resume</c>: a recorded job; its split stays as it was made.</summary>
    Resume,

    /// <summary><c>demo</c>: the sample program on the built-in simulator.</summary>
    Demo,

    /// <summary>The operator's console commands (<c>status</c>, <c>home</c>, <c>jog</c>, ...): a controller, the job store, the settings.</summary>
    Console,
}

/// <summary>
/// The options stream, resume and demo share, bound to one <see cref="RunSettings"/>: the settings file (or the
/// job's recorded settings, or the defaults) first, then only the options given on the command line.
/// </summary>
internal sealed class JobOptions
{
    private static readonly RunSettings D = RunSettings.Default;

    private readonly Option<bool> _sim = new("--sim") { Description = "Stream into the built-in simulator." };
    private readonly Option<string?> _tcp = new("--tcp") { Description = "Stream to a controller over Ethernet: HOST[:PORT] (port 1025 by default), or PORT alone on 127.0.0.1." };
    private readonly Option<string?> _serial = new("--serial") { Description = "Stream over RS-232: DEV[,BAUD] (38400 by default)." };
    private readonly Option<bool> _yes = new("--yes", "-y") { Description = "Confirm a start from a line / restart without asking." };
    private readonly Option<string?> _jobDb = new("--job-db") { Description = "The store as an SQLite file (the same as --store sqlite:PATH): jobs and checkpoints for crash-safe resume." };
    private readonly Option<string?> _store = StoreOptions.Option();
    private readonly Option<string?> _station = new("--station") { Description = "This station's name in the job history (default: the host name)." };
    private readonly Option<string?> _machine = new("--machine") { Description = "The machine's name in the job history (default: its connection, host:port or the serial device)." };
    private readonly Option<string?> _settings = new("--settings") { Description = "Run settings file (JSON); default $PMACSTREAM_SETTINGS or ~/.pmacstream/settings.json when it exists." };
    private readonly Option<int?> _bufferWords = new("--buffer-words") { Description = $"Rotary buffer size in words (default {D.BufferWords}; the simulator's is defined to this)." };
    private readonly Option<int?> _packetsInFlight = new("--packets-in-flight") { Description = $"full strategy over Ethernet: WRITEBUFFER packets sent before their replies (default {D.PacketsInFlight}; 1: one at a time)." };
    private readonly Option<int?> _bufferCap = new("--buffer-cap") { Description = "full strategy: most words of a rotary buffer sized from the controller's SIZE (default: no cap)." };
    private readonly Option<int?> _tickMs = new("--tick-ms") { Description = $"Timer period of the streaming tick, milliseconds (default {D.TickPeriod.TotalMilliseconds:0})." };
    private readonly Option<string?> _window = new("--window") { Description = $"Download window of the chunk strategy, as fractions of a chunk (default {D.Window}: lines 600-700 of a 1000-line chunk) or percent (60-70%)." };
    private readonly Option<double?> _safeZ = new("--safe-z") { Description = $"Safe Z (work coordinates) for the approach when starting from a line (default {D.SafeZ}; --safe-z-mode fixed, and the fallback of highest)." };
    private readonly Option<string?> _safeZMode = new("--safe-z-mode") { Description = "Safe Z when starting from a line: fixed (--safe-z, the default) or highest (the highest Z reached so far plus --clearance). The HMI plans the same way." };
    private readonly Option<double?> _feedOverride = new("--feed-override")
    {
        Description = $"Feed override in percent ({FeedOverrides.Minimum}-{FeedOverrides.Maximum}, &1 %), the operator's feed control as on the HMI: the program's feeds stay as programmed (in P500 in paper mode) and run at this share. stream starts with it (default {FeedOverrides.Default}); resume sets it when given.",
    };

    private readonly Option<string?> _stops = new("--stops")
    {
        Description = "At a program stop (M00, M01 with optional stop on): wait (print 'program stop (M00) at line N' and wait for Enter; the default on a terminal) or continue (go on by itself: scripted runs, the simulator). Without a terminal a program with stops needs --stops continue.",
        HelpName = "wait|continue",
    };

    private readonly Option<string?> _optionalStop = new("--optional-stop")
    {
        Description = "Optional stop: on (M01 stops, the default) or off (M01 runs through). Set on the controller (P502), no new split needed.",
        HelpName = "on|off",
    };

    private readonly Option<bool> _loadLibrary = new("--load-library")
    {
        Description = "Download the PROG 1000/1001 library of the profile and the machine's tables before the job's first chunk, only while the coordinate system is idle (otherwise the controller must already run it: P7000/P7001 are checked; --force runs anyway).",
    };

    private readonly Option<bool> _noHomeCheck = new("--no-home-check")
    {
        Description = "Start even if an axis is not homed (Home Complete clear): the operator knows the machine's position (absolute encoders). Without it a job on an unhomed machine is refused.",
    };

    private readonly Option<double?> _clearance = new("--clearance") { Description = $"Added to the highest Z so far with --safe-z-mode highest (default {D.Clearance})." };
    private readonly Option<string> _simSpeed;
    private ChunkShapeOptions? _shape;

    private JobOptions(JobFace face)
    {
        _simSpeed = new Option<string>("--sim-speed") { Description = "Simulator clock: realtime, Nx (e.g. 20x) or instant.", DefaultValueFactory = _ => face == JobFace.Demo ? "60x" : "20x" };
    }

    /// <summary>Adds the options for <paramref name="face"/> to <paramref name="cmd"/>.</summary>
    public static JobOptions AddTo(Command cmd, JobFace face)
    {
        var o = new JobOptions(face);
        var options = new List<Option>();
        if (face == JobFace.Console)
        {
            options.AddRange([o._sim, o._tcp, o._serial, o._jobDb, o._store, o._station, o._machine, o._settings, o._simSpeed]);
        }
        else
        {
            if (face != JobFace.Demo)
            {
                options.AddRange([o._sim, o._tcp, o._serial, o._yes, o._jobDb, o._store, o._station, o._machine, o._safeZ, o._safeZMode, o._clearance, o._feedOverride, o._stops, o._optionalStop, o._loadLibrary, o._noHomeCheck]);
            }

            options.AddRange([o._settings, o._simSpeed, o._bufferWords, o._packetsInFlight, o._bufferCap, o._tickMs, o._window]);
        }

        foreach (var option in options)
        {
            cmd.Options.Add(option);
        }

        // Only stream splits: resume keeps its split as it was made, the demo uses the defaults.
        o._shape = face == JobFace.Stream ? ChunkShapeOptions.AddTo(cmd) : null;
        return o;
    }

    /// <summary>These options as one command line gives them, for its handler.</summary>
    public JobArgs Bind(ParseResult parse) => new(this, parse);

    /// <summary>What the job does about the controller's library: load it (<c>--load-library</c>), only warn (<paramref name="forced"/>), else verify it.</summary>
    public LibraryPolicy Library(ParseResult parse, bool forced) =>
        parse.GetValue(_loadLibrary) ? LibraryPolicy.Load : forced ? LibraryPolicy.Force : LibraryPolicy.Verify;

    /// <summary>True when the operator overrode the home check (<c>--no-home-check</c>).</summary>
    public bool NoHomeCheck(ParseResult parse) => parse.GetValue(_noHomeCheck);

    /// <summary>The settings file named with <c>--settings</c>, or null for the default.</summary>
    public string? SettingsPath(ParseResult parse) => parse.GetValue(_settings);

    /// <summary>True when the operator confirmed starts from a line with <c>--yes</c>.</summary>
    public bool Yes(ParseResult parse) => parse.GetValue(_yes);

    /// <summary>The feed override given with <c>--feed-override</c> (percent), or null.</summary>
    public double? FeedOverride(ParseResult parse)
    {
        try
        {
            return parse.GetValue(_feedOverride) is { } percent ? FeedOverrides.Validate(percent) : null;
        }
        catch (JobException e)
        {
            throw new CliException("--feed-override: " + e.Message);
        }
    }

    /// <summary>Optional stop: <c>--optional-stop on|off</c>, on unless told.</summary>
    public bool OptionalStop(ParseResult parse) => parse.GetValue(_optionalStop)?.Trim().ToLowerInvariant() switch
    {
        null or "on" => true,
        "off" => false,
        var other => throw new CliException($"--optional-stop {other}: expected on or off"),
    };

    /// <summary>
    /// True when the job goes on by itself at program stops (<c>--stops continue</c>). Without <c>--stops</c> it waits for
    /// Enter on a terminal; when input is not a terminal, a program that stops (its manifest's stop codes, M01 only
    /// with optional stop on) is refused here rather than left waiting for an Enter that cannot come.
    /// </summary>
    public bool ContinueAtStops(ParseResult parse, Preparation.ChunkManifest manifest, GCode.MachineProfile profile)
    {
        switch (parse.GetValue(_stops)?.Trim().ToLowerInvariant())
        {
            case "continue":
                return true;
            case "wait":
                return false;
            case null:
                break;
            case var other:
                throw new CliException($"--stops {other}: expected wait or continue");
        }

        var optional = OptionalStop(parse);
        var stops = (manifest.StopCodes ?? new Dictionary<string, int>())
            .Where(c => optional || profile.Find(c.Key[0], double.Parse(c.Key.AsSpan(1), CultureInfo.InvariantCulture))?.Stop != GCode.ProgramStopKind.Optional)
            .ToDictionary(c => c.Key, c => c.Value);
        if (stops.Count > 0 && CliConsole.Of(parse).InputRedirected)
        {
            throw new CliException($"the program stops at {ProgramGate.Describe(stops)} and input is not a terminal, so Enter cannot continue it: give --stops continue to go on at each stop by itself (or --stops wait to read Enter from the input)");
        }

        return false;
    }

    /// <summary>The job database named with <c>--job-db</c>, or null for the default.</summary>
    public string? JobDatabase(ParseResult parse) => parse.GetValue(_jobDb);

    /// <summary>The store: <c>--store</c>, <c>--job-db</c>, the settings file's <c>store</c>, <c>$PMACSTREAM_STORE</c>, or the default file.</summary>
    public Preparation.Store.StoreLocation Store(ParseResult parse) => StoreOptions.Resolve(parse.GetValue(_store), parse.GetValue(_jobDb), SettingsPath(parse));

    /// <summary>The station: <c>--station</c>, else the settings file's <c>station</c>, else the host name.</summary>
    public string Station(ParseResult parse) => StationSettings(parse).StationName(parse.GetValue(_station));

    /// <summary>The settings file's station part (store, station, lease times).</summary>
    public StationSettings StationSettings(ParseResult parse)
    {
        try
        {
            return Jobs.StationSettings.Load(SettingsPath(parse));
        }
        catch (Exception e) when (e is RunSettingsException or IOException)
        {
            throw new CliException(Preparation.Store.StoreLocation.Redact(e.Message));
        }
    }

    /// <summary>
    /// Takes the lease of the machine at <paramref name="target"/> for this station before anything is sent to it:
    /// <c>--machine</c>, else <paramref name="recorded"/> (a resumed job's machine), else its connection. Null for the
    /// built-in simulator (each process has its own). Refused (exit 1) with who holds it.
    /// </summary>
    public MachineLease? Lease(ParseResult parse, ConnectionSpec target, string? recorded = null, long? jobId = null)
    {
        if (target.IsSimulator)
        {
            return null;
        }

        var machine = Machine(parse) ?? recorded ?? JobService.MachineName(target);
        return MachineLease.Take(Store(parse), machine, Station(parse), jobId, StationSettings(parse));
    }

    /// <summary>The machine (<c>--machine</c>), or null for its connection.</summary>
    public string? Machine(ParseResult parse) => parse.GetValue(_machine);

    /// <summary>The simulator's clock.</summary>
    public SimSpeed SimSpeed(ParseResult parse)
    {
        try
        {
            return Sim.SimSpeed.Parse(parse.GetValue(_simSpeed)!);
        }
        catch (FormatException e)
        {
            throw new CliException(e.Message);
        }
    }

    /// <summary>The controller chosen (<c>--sim</c>, <c>--tcp</c>, <c>--serial</c>), or null.</summary>
    public ConnectionSpec? Target(ParseResult parse)
    {
        var chosen = new List<ConnectionSpec>();
        try
        {
            if (parse.GetValue(_sim))
            {
                chosen.Add(ConnectionSpec.Simulator);
            }

            if (parse.GetValue(_tcp) is { Length: > 0 } tcp)
            {
                chosen.Add(ConnectionSpec.Ethernet(tcp));
            }

            if (parse.GetValue(_serial) is { Length: > 0 } serial)
            {
                var comma = serial.IndexOf(',');
                chosen.Add(comma < 0 ? ConnectionSpec.Parse("serial:" + serial) : ConnectionSpec.Parse($"serial:{serial[..comma]}@{serial[(comma + 1)..]}"));
            }
        }
        catch (FormatException e)
        {
            throw new CliException(e.Message);
        }

        return chosen.Count switch
        {
            0 => null,
            1 => chosen[0],
            _ => throw new CliException("choose one of --sim, --tcp and --serial"),
        };
    }

    /// <summary>
    /// The run settings: <c>--settings FILE</c> when given, else <paramref name="recorded"/> (a resumed job's own),
    /// else the default settings file or the defaults; then the options given on the command line.
    /// </summary>
    public RunSettings Settings(ParseResult parse, RunSettings? recorded = null)
    {
        var s = parse.GetValue(_settings) is { } file ? RunSettingsFile.Load(file) : recorded ?? RunSettingsFile.Load();
        s = _shape is null ? s : s with { Shape = _shape.Apply(parse, s.Shape) };

        if (parse.GetValue(_bufferWords) is { } words)
        {
            s = s with { BufferWords = words };
        }

        if (parse.GetValue(_packetsInFlight) is { } inFlight)
        {
            s = s with { PacketsInFlight = inFlight is >= 1 and <= 64 ? inFlight : throw new CliException("--packets-in-flight must be between 1 and 64") };
        }

        if (parse.GetValue(_bufferCap) is { } cap)
        {
            s = s with { BufferWordsCap = cap >= 0 ? cap : throw new CliException("--buffer-cap must be 0 (no cap) or more") };
        }

        if (parse.GetValue(_tickMs) is { } tick)
        {
            s = s with { TickPeriod = tick is >= 5 and <= 10_000 ? TimeSpan.FromMilliseconds(tick) : throw new CliException("--tick-ms must be between 5 and 10000") };
        }

        if (parse.GetValue(_window) is { } window)
        {
            try
            {
                var (start, end) = RunSettings.ParseWindow(window);
                s = s with { WindowStart = start, WindowEnd = end };
            }
            catch (FormatException e)
            {
                throw new CliException("--" + e.Message);
            }
        }

        if (parse.GetValue(_safeZMode) is { } mode)
        {
            try
            {
                s = s with { SafeZMode = RunSettingsFile.ParseSafeZMode(mode) };
            }
            catch (FormatException e)
            {
                throw new CliException("--safe-z-mode: " + e.Message);
            }
        }

        s = parse.GetValue(_safeZ) is { } z ? s with { SafeZ = z } : s;
        s = parse.GetValue(_clearance) is { } c ? s with { Clearance = c } : s;
        try
        {
            s.Validate();
        }
        catch (ArgumentException e)
        {
            throw new CliException(e.Message);
        }

        return s;
    }

    /// <summary>The connection spec of a job record, as <c>resume</c> reopens it.</summary>
    public static ConnectionSpec RecordedTarget(string spec)
    {
        try
        {
            return ConnectionSpec.Parse(spec);
        }
        catch (FormatException e)
        {
            throw new CliException(string.Create(CultureInfo.InvariantCulture, $"the job's connection cannot be reopened ({e.Message}): give --sim, --tcp or --serial"));
        }
    }
}
