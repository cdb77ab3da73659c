using PmacStream.Pmac;

namespace PmacStream.Streaming;

/// <summary>The operator's commands: hold, resume (after a hold or at a program stop), step, abort, feed, optional stop, single block.</summary>
public sealed partial class StreamingSession
{
    /// <summary>Feed hold (<c>&amp;n H</c>).</summary>
    public Task HoldAsync(CancellationToken cancellationToken = default) =>
        CommandAsync(_cs.Hold, "hold", SessionState.Held, cancellationToken);

    /// <summary>Resume motion after a hold or at a program stop (<c>&amp;n R</c>, or <c>&amp;n S</c> in single-block mode).</summary>
    public Task ResumeMotionAsync(CancellationToken cancellationToken = default) =>
        CommandAsync(RunCommand, _singleBlock ? "step" : "resume", SessionState.Running, cancellationToken);

    /// <summary>Run one more block (<c>&amp;n S</c>), the single-block start.</summary>
    public Task StepAsync(CancellationToken cancellationToken = default) =>
        CommandAsync(_cs.Step, "step", SessionState.Running, cancellationToken);

    /// <summary>Abort (<c>&amp;n A</c>): motion stops at once; the job stays resumable from the last executed line.</summary>
    public Task AbortAsync(CancellationToken cancellationToken = default) =>
        CommandAsync(_cs.Abort, "abort", SessionState.Aborted, cancellationToken);

    /// <summary>
    /// The controller stopped the job on an alarm (a limit, a fault kill aborted the program; the host sent nothing):
    /// the session ends as <see cref="SessionState.Faulted"/> with <paramref name="message"/> and a durable checkpoint
    /// at the last executed block, so a resume after the alarm is cleared restarts exactly there.
    /// </summary>
    public async Task HaltOnAlarmAsync(string message, CancellationToken cancellationToken = default)
    {
        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            if (_state is SessionState.Completed or SessionState.Faulted)
            {
                return;
            }

            _state = SessionState.Faulted;
            _log.Message = message;
            Log.Error("Streaming stopped by a controller alarm: {Message}", message);
            Raise(StreamingEventKind.Fault, message, _currentChunk);
            SaveCheckpoint(durable: true);
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
    }

    /// <summary>
    /// The optional-stop switch on or off (the variable the library's <c>M01</c> routine reads, <c>P502=1</c>): the
    /// next M01 the controller reaches stops or not. Sent between ticks, never into an open buffer; before a start it
    /// is only remembered (the start sends it).
    /// </summary>
    public Task SetOptionalStopAsync(bool on, CancellationToken cancellationToken = default)
    {
        _optionalStop = on;
        return _state is SessionState.Idle or SessionState.Completed
            ? Task.CompletedTask
            : CommandAsync(OptionalStopCommand, on ? "optional stop on" : "optional stop off", null, cancellationToken);
    }

    /// <summary>Single-block mode on or off: following starts run one block each.</summary>
    public void SetSingleBlock(bool on)
    {
        _singleBlock = on;
        Raise(StreamingEventKind.Command, on ? "single-block mode on" : "single-block mode off", _currentChunk);
    }

    /// <summary>
    /// Live feed change: <c>P500=value</c> in paper mode (feed units), <c>&amp;n %value</c> in override mode (percent).
    /// Sent between ticks, never into an open buffer.
    /// </summary>
    public Task SetFeedAsync(double value, CancellationToken cancellationToken = default)
    {
        if (value < 0 || double.IsNaN(value) || double.IsInfinity(value))
        {
            throw new ArgumentOutOfRangeException(nameof(value), "feed must be a finite non-negative number");
        }

        var cmd = _cs.SetFeed(value, out var v);
        return CommandAsync(cmd, $"feed {v}", null, cancellationToken, () => _pace.Feed = value);
    }

    private async Task CommandAsync(string command, string what, SessionState? then, CancellationToken cancellationToken, Action? onSent = null)
    {
        if (_state is SessionState.Idle or SessionState.Completed)
        {
            throw new InvalidOperationException($"cannot {what}: the session is {_state}");
        }

        await _gate.WaitAsync(cancellationToken).ConfigureAwait(false);
        try
        {
            await _channel.OnlineAsync(command, cancellationToken).ConfigureAwait(false);
            onSent?.Invoke();
            if (then is { } s && _state is not (SessionState.Faulted or SessionState.Completed))
            {
                if (_state == SessionState.Stopped && s == SessionState.Running)
                {
                    // The run command continues after the stop's STOP; the next ticks see the program move on.
                    what = $"{what} after the {_stops.Stop}";
                    _stops.Continued();
                }

                _state = s;
            }

            Raise(StreamingEventKind.Command, what, _currentChunk);
            SaveCheckpoint(durable: then == SessionState.Aborted);
        }
        catch (Exception e) when (e is PmacLinkException or PmacErrorException)
        {
            Fault(e);
            throw;
        }
        finally
        {
            _gate.Release();
        }

        PublishStatus();
    }
}
