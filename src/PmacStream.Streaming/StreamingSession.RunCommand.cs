namespace PmacStream.Streaming;

/// <summary>The run command of a start, and finishing a start that broke off around it (<see cref="RunCommandRule"/>).</summary>
public sealed partial class StreamingSession
{
    private string RunCommand => _cs.Run(_singleBlock);

    /// <summary>
    /// After a fault, for a start whose run command is not known to have arrived (the link may have lost the command or
    /// only its reply): gives it only when the controller has not started the program, loading the start again first
    /// when the load broke off. False (with the reason in the status message) when the load broke off yet the
    /// coordinate system runs or ran something: not this start.
    /// </summary>
    private async Task<bool> FinishBrokenStartAsync(CancellationToken cancellationToken)
    {
        var seen = await _queries.ReadAsync(null, cancellationToken).ConfigureAwait(false);
        if (RunCommandRule.WhyNot(seen, Program.Sync.Variable) is { } arrived)
        {
            if (!_start.Loaded)
            {
                _log.Message = $"still cannot continue: the start had not finished loading the buffer, yet {arrived}; check what the controller runs";
                return false;
            }

            Log.Information("recover: {Why:l}", arrived);
        }
        else
        {
            // Nothing has run. When the loading (preamble, first chunk) broke off, how much of it arrived is not
            // known: clear the buffer and load it again.
            if (!_start.Loaded)
            {
                await _start.LoadAsync(cancellationToken).ConfigureAwait(false);
                SaveCheckpoint(durable: true);
            }

            await _channel.OnlineAsync(RunCommand, cancellationToken).ConfigureAwait(false);
        }

        _runSent = true;
        return true;
    }
}
