namespace PmacStream.Preparation;

/// <summary>
/// A bounded first-in first-out hand-over between one producing and one consuming thread. Waiting blocks on the
/// monitor instead of spinning (BlockingCollection's semaphore spins first, which on a loaded two-core machine
/// burns the CPU the other side needs). Order is kept exactly: items come out as they went in.
/// </summary>
internal sealed class HandOff<T> : IDisposable
{
    private readonly Queue<T> _items;
    private readonly int _capacity;
    private readonly CancellationTokenRegistration _registration;
    private readonly CancellationToken _ct;
    private bool _completed;

    public HandOff(int capacity, CancellationToken ct)
    {
        _capacity = capacity;
        _items = new Queue<T>(capacity);
        _ct = ct;
        _registration = ct.Register(static s => ((HandOff<T>)s!).Wake(), this);
    }

    /// <summary>Adds an item, waiting while the queue is full. Throws when cancelled or completed.</summary>
    public void Add(T item)
    {
        lock (_items)
        {
            while (_items.Count >= _capacity && !_completed)
            {
                _ct.ThrowIfCancellationRequested();
                Monitor.Wait(_items);
            }

            _ct.ThrowIfCancellationRequested();
            if (_completed)
            {
                throw new InvalidOperationException("hand-over completed");
            }

            _items.Enqueue(item);
            if (_items.Count == 1)
            {
                Monitor.PulseAll(_items);
            }
        }
    }

    /// <summary>Takes the next item, waiting while the queue is empty; false once it is completed and drained.</summary>
    public bool TryTake(out T item)
    {
        lock (_items)
        {
            while (_items.Count == 0)
            {
                _ct.ThrowIfCancellationRequested();
                if (_completed)
                {
                    item = default!;
                    return false;
                }

                Monitor.Wait(_items);
            }

            item = _items.Dequeue();
            // A producer waiting on a full queue is woken at half full, not at the first free place: it then adds
            // several items per wake (one wake and switch per chunk was ~30,000 for a gigabyte program). Every take
            // passes this count on the way down, so a waiting producer is always woken.
            if (_items.Count == _capacity / 2)
            {
                Monitor.PulseAll(_items);
            }

            return true;
        }
    }

    /// <summary>No more items: the taker drains what is queued, then sees the end; further adds throw.</summary>
    public void Complete()
    {
        lock (_items)
        {
            _completed = true;
            Monitor.PulseAll(_items);
        }
    }

    public bool IsCompleted
    {
        get
        {
            lock (_items)
            {
                return _completed;
            }
        }
    }

    public void Dispose() => _registration.Dispose();

    private void Wake()
    {
        lock (_items)
        {
            Monitor.PulseAll(_items);
        }
    }
}
