using PmacStream.Machine;

namespace PmacStream.Hmi;

/// <summary>Jog, MDI, touch-off and load library.</summary>
public sealed partial class ConsolePresenter
{
    /// <summary>MDI blocks kept in the history (oldest dropped).</summary>
    public const int MdiHistoryLength = 50;

    /// <summary>A jog button pressed: one increment at the panel's speed, or the start of a continuous jog.</summary>
    private async Task<ConsoleResult> JogAsync(int direction, CancellationToken cancellationToken)
    {
        var axis = _view.JogAxis;
        if (_view.JogIncrement is { } step)
        {
            return await _backend.JogAsync(axis, direction * step, _view.JogFeed, cancellationToken).ConfigureAwait(true);
        }

        _jogHeld = true;
        // The panel's speed holds for a continuous jog too (the motor's own jog speed is given back when it stops).
        var result = await _backend.StartJogAsync(axis, direction, _view.JogFeed, cancellationToken).ConfigureAwait(true);
        if (result.Done && !_jogHeld)
        {
            // Released while the start was on its way: the jog stops at once.
            return await _backend.StopJogAsync(axis, cancellationToken).ConfigureAwait(true);
        }

        _continuousAxis = result.Done ? axis : null;
        return result;
    }

    /// <summary>The jog button released: a continuous jog stops (an increment runs to its end).</summary>
    private void StopContinuousJog()
    {
        _jogHeld = false;
        if (_continuousAxis is { } axis)
        {
            _continuousAxis = null;
            Command(c => _backend.StopJogAsync(axis, c));
        }
    }

    /// <summary>Sends the MDI line; done, it goes into the history and the line is emptied for the next block.</summary>
    private async Task MdiAsync()
    {
        var block = _view.MdiText.Trim();
        if (block.Length == 0)
        {
            return;
        }

        if (!_backend.ConsoleReady)
        {
            _view.ConsoleMessage = HmiText.Get(TextId.ConnectFirst, Language);
            return;
        }

        var result = await _backend.MdiAsync([block], _life.Token).ConfigureAwait(true);
        ShowResult(result);
        if (_mdiHistory.Count == 0 || _mdiHistory[^1] != block)
        {
            _mdiHistory.Add(block);
            if (_mdiHistory.Count > MdiHistoryLength)
            {
                _mdiHistory.RemoveAt(0);
            }

            _view.MdiHistory = [.. _mdiHistory];
        }

        if (result.Done)
        {
            _view.MdiText = string.Empty;
        }
    }

    /// <summary>Touch-off in the active work offset (G54 before the library chose one), then the grid shows the new value.</summary>
    private async Task TouchOffAsync(string axis)
    {
        if (!_backend.ConsoleReady)
        {
            _view.ConsoleMessage = HmiText.Get(TextId.ConnectFirst, Language);
            return;
        }

        var table = State?.WorkOffset is { } active && MachineTables.IndexOf(active) is not null ? active : MachineTables.Names[0];
        var result = await _backend.TouchOffAsync(table, axis, _view.TouchValue, _life.Token).ConfigureAwait(true);
        ShowResult(result);
        if (result.Done)
        {
            await ReloadTablesAsync().ConfigureAwait(true);
        }
    }

    /// <summary>Downloads the chosen profile's library and tables (the built-in simulator), then reads the tables again.</summary>
    private async Task LoadLibraryAsync()
    {
        if (!_backend.ConsoleReady)
        {
            _view.ConsoleMessage = HmiText.Get(TextId.ConnectFirst, Language);
            return;
        }

        var profile = _profile();
        await _hmi.LoadLibraryAsync(profile, _life.Token).ConfigureAwait(true);
        _view.ConsoleMessage = T(TextId.LibraryLoaded, profile.Name);
        await ReloadTablesAsync().ConfigureAwait(true);
    }
}
