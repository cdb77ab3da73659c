namespace PmacStream.Hmi;

/// <summary>
/// The operations the view's events start (connect, check, split, execute...): each runs on the UI thread as it
/// arrives; while any runs the screen's commands are disabled, a failure is reported instead of thrown into the
/// message loop, and afterwards the screen is refreshed. Tests await <see cref="WhenIdleAsync"/>.
/// </summary>
internal sealed class ViewOperations(CancellationToken life, Action changed, Action<Exception> failed)
{
    private readonly List<Task> _pending = [];

    /// <summary>Operations under way.</summary>
    public int Busy { get; private set; }

    /// <summary>Starts <paramref name="operation"/>.</summary>
    public void Run(Func<Task> operation)
    {
        var task = RunGuarded(operation);
        lock (_pending)
        {
            _pending.Add(task);
        }
    }

    /// <summary>Completes when every operation started so far (and those they started) has finished.</summary>
    public async Task WhenIdleAsync()
    {
        while (true)
        {
            Task[] pending;
            lock (_pending)
            {
                _pending.RemoveAll(t => t.IsCompleted);
                pending = [.. _pending];
            }

            if (pending.Length == 0)
            {
                return;
            }

            await Task.WhenAll(pending).ConfigureAwait(true);
        }
    }

    private async Task RunGuarded(Func<Task> operation)
    {
        Busy++;
        changed();
        try
        {
            await operation().ConfigureAwait(true);
        }
        catch (OperationCanceledException) when (life.IsCancellationRequested)
        {
        }
        catch (Exception e)
        {
            failed(e);
        }
        finally
        {
            Busy--;
            changed();
        }
    }
}
