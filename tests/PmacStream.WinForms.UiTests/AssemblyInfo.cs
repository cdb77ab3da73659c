// The Wine tests share one Wine prefix (and so one wineserver, one keyboard focus and the file dialog's state): two
// forms driven at once type into each other's dialogs. They run one after the other.
[assembly: Xunit.CollectionBehavior(DisableTestParallelization = true)]
