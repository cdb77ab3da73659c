using Serilog;

namespace PmacStream.Hmi;

/// <summary>The connection panel's logic: the controller link the jobs run on, and the state text beside it.</summary>
internal sealed class ConnectionPanel(IMainView view, IHmiBackend backend, ILogger log) : IAsyncDisposable
{
    /// <summary>The open link's description, null when not connected (the backend holds the link).</summary>
    public string? Link { get; private set; }

    /// <summary>True while a connection is being made.</summary>
    public bool Connecting { get; private set; }

    /// <summary>Connects with what the panel holds (nothing when already connected); the simulator gets <paramref name="profile"/>'s library.</summary>
    public async Task ConnectAsync(GCode.MachineProfile profile, HmiLanguage language, CancellationToken cancellationToken)
    {
        if (Link is not null)
        {
            return;
        }

        var settings = view.ConnectionSettings;
        Connecting = true;
        view.ConnectionState = HmiText.Get(TextId.StateConnecting, language);
        try
        {
            Link = await backend.ConnectAsync(settings, profile, cancellationToken).ConfigureAwait(true);
            log.Information("Connected to {Device:l}", Link);
        }
        finally
        {
            Connecting = false;
            ShowState(language);
        }
    }

    /// <summary>Closes the link; refused while <paramref name="jobActive"/>.</summary>
    public async Task DisconnectAsync(bool jobActive, HmiLanguage language)
    {
        if (jobActive)
        {
            throw new InvalidOperationException("A job is running: hold or abort it before disconnecting.");
        }

        if (Link is { } c)
        {
            Link = null;
            await backend.DisconnectAsync().ConfigureAwait(true);
            log.Information("Disconnected from {Device:l}", c);
        }

        ShowState(language);
    }

    /// <summary>Shows the state in <paramref name="language"/>.</summary>
    public void ShowState(HmiLanguage language) =>
        view.ConnectionState = Link is null ? HmiText.Get(TextId.StateDisconnected, language) : HmiText.Format(TextId.StateConnected, language, Link);

    /// <inheritdoc />
    /// <remarks>No view calls: the window may already be gone.</remarks>
    public async ValueTask DisposeAsync()
    {
        if (Link is not null)
        {
            Link = null;
            await backend.DisconnectAsync().ConfigureAwait(false);
        }
    }
}
