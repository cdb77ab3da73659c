using System.CommandLine;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Cli.Commands;

/// <summary>
/// The job options of one command line, bound: what a handler asks of them. Each value is read and checked when the
/// handler asks, in the handler's order, so a bad value is reported where the command always reported it.
/// </summary>
internal sealed class JobArgs(JobOptions options, ParseResult parse)
{
    /// <inheritdoc cref="JobOptions.Library"/>
    public LibraryPolicy Library(bool forced) => options.Library(parse, forced);

    /// <inheritdoc cref="JobOptions.NoHomeCheck"/>
    public bool NoHomeCheck => options.NoHomeCheck(parse);

    /// <inheritdoc cref="JobOptions.SettingsPath"/>
    public string? SettingsPath => options.SettingsPath(parse);

    /// <inheritdoc cref="JobOptions.Yes"/>
    public bool Yes => options.Yes(parse);

    /// <inheritdoc cref="JobOptions.FeedOverride"/>
    public double? FeedOverride() => options.FeedOverride(parse);

    /// <inheritdoc cref="JobOptions.OptionalStop"/>
    public bool OptionalStop() => options.OptionalStop(parse);

    /// <inheritdoc cref="JobOptions.ContinueAtStops"/>
    public bool ContinueAtStops(Preparation.ChunkManifest manifest, GCode.MachineProfile profile) => options.ContinueAtStops(parse, manifest, profile);

    /// <inheritdoc cref="JobOptions.Store"/>
    public Preparation.Store.StoreLocation Store() => options.Store(parse);

    /// <inheritdoc cref="JobOptions.Station"/>
    public string Station() => options.Station(parse);

    /// <inheritdoc cref="JobOptions.Lease"/>
    public MachineLease? Lease(ConnectionSpec target, string? recorded = null, long? jobId = null) => options.Lease(parse, target, recorded, jobId);

    /// <inheritdoc cref="JobOptions.Machine"/>
    public string? Machine => options.Machine(parse);

    /// <inheritdoc cref="JobOptions.SimSpeed"/>
    public SimSpeed SimSpeed() => options.SimSpeed(parse);

    /// <inheritdoc cref="JobOptions.Target"/>
    public ConnectionSpec? Target() => options.Target(parse);

    /// <inheritdoc cref="JobOptions.Settings"/>
    public RunSettings Settings(RunSettings? recorded = null) => options.Settings(parse, recorded);
}
