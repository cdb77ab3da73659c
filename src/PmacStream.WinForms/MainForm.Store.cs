using PmacStream.Hmi;

namespace PmacStream.WinForms;

/// <summary>
/// The Store page (<see cref="ConsoleLayout"/>'s store boxes): the store's job history (the records <c>jobs --json</c>
/// prints) and its program revisions, Refresh and Open. A passive <see cref="IStoreView"/>: <see cref="StorePresenter"/> decides.
/// </summary>
internal sealed partial class MainForm : IStoreView
{
    private readonly TabPage tabStore = new() { Name = nameof(tabStore), Text = "Store" };
    private readonly Label lblStoreLocation = new() { AutoEllipsis = true };
    private readonly DataGridView gridStoreJobs = NewGrid();
    private readonly Label lblStoreShop = new() { Text = "Shop: machines, who runs what, the current line" };
    private readonly DataGridView gridStoreShop = NewGrid();
    private readonly Label lblStorePrograms = new() { Text = "Programs in the store" };
    private readonly DataGridView gridStorePrograms = NewGrid();
    private readonly Button btnStoreRefresh = new() { Name = nameof(btnStoreRefresh), Text = "Refresh" };
    private readonly Button btnStoreOpen = new() { Name = nameof(btnStoreOpen), Text = "Open program" };
    private readonly Label lblStoreMessage = new() { AutoEllipsis = true };

    public event EventHandler? StoreRefreshRequested;
    public event EventHandler? OpenStoredProgramRequested;

    private string _storeLocation = string.Empty;

    public string StoreLocationText
    {
        set
        {
            _storeLocation = value;
            lblStoreLocation.Text = string.Format(System.Globalization.CultureInfo.InvariantCulture, _texts[TextId.StoreLocation], value);
        }
    }

    /// <summary>The Store page's texts in the chosen language (called with the console's).</summary>
    private void ApplyStoreTexts()
    {
        var t = _texts;
        (tabStore.Text, lblStorePrograms.Text, btnStoreRefresh.Text, btnStoreOpen.Text) = (t[TextId.TabStore], t[TextId.StorePrograms], t[TextId.StoreRefresh], t[TextId.StoreOpen]);
        StoreLocationText = _storeLocation;
        TextId[] jobs = [TextId.StoreColJob, TextId.StoreColProgram, TextId.StoreColStation, TextId.StoreColMachine, TextId.StoreColStarted, TextId.StoreColEnded, TextId.StoreColOutcome, TextId.StoreColBlocks];
        TextId[] programs = [TextId.StoreColId, TextId.StoreColName, TextId.StoreColProfile, TextId.StoreColBlocks, TextId.StoreColErrors];
        for (var c = 0; c < jobs.Length && c < gridStoreJobs.Columns.Count; c++)
        {
            gridStoreJobs.Columns[c].HeaderText = t[jobs[c]];
        }

        for (var c = 0; c < programs.Length && c < gridStorePrograms.Columns.Count; c++)
        {
            gridStorePrograms.Columns[c].HeaderText = t[programs[c]];
        }
    }

    public IReadOnlyList<StoredJobRow> StoredJobs
    {
        set
        {
            gridStoreJobs.Rows.Clear();
            foreach (var j in value)
            {
                gridStoreJobs.Rows.Add(j.Id, j.Program, j.Station, j.Machine, j.Started, j.Ended, j.Outcome, j.Blocks);
            }
        }
    }

    public IReadOnlyList<StoredProgramRow> StoredPrograms
    {
        set
        {
            gridStorePrograms.Rows.Clear();
            foreach (var p in value)
            {
                gridStorePrograms.Rows.Add(p.Id, p.Name, p.Profile, p.Blocks, p.Errors);
            }
        }
    }

    public IReadOnlyList<ShopRow> Shop
    {
        set
        {
            gridStoreShop.Rows.Clear();
            foreach (var m in value)
            {
                gridStoreShop.Rows.Add(m.Machine, m.Station, m.Job, m.Program, m.Line, m.Blocks, m.Outcome, m.Lease);
            }
        }
    }

    public long? SelectedStoredProgram =>
        gridStorePrograms.CurrentRow?.Cells[0].Value is long id ? id : null;

    public string StoreMessage
    {
        set => lblStoreMessage.Text = value;
    }

    /// <summary>The Store tab beside the console's pages.</summary>
    private void PlaceStore()
    {
        tabConsole.TabPages.Add(tabStore);
        Place(lblStoreLocation, ConsoleLayout.StoreLocationLabel, tabStore);
        Place(gridStoreJobs, ConsoleLayout.StoreJobsGrid, tabStore);
        Place(lblStoreShop, ConsoleLayout.StoreShopLabel, tabStore);
        Place(gridStoreShop, ConsoleLayout.StoreShopGrid, tabStore);
        Place(lblStorePrograms, ConsoleLayout.StoreProgramsLabel, tabStore);
        Place(gridStorePrograms, ConsoleLayout.StoreProgramsGrid, tabStore);
        Place(btnStoreRefresh, ConsoleLayout.StoreRefreshButton, tabStore);
        Place(btnStoreOpen, ConsoleLayout.StoreOpenButton, tabStore);
        Place(lblStoreMessage, ConsoleLayout.StoreMessageLabel, tabStore);
        foreach (var c in new[] { "Job", "Program", "Station", "Machine", "Started", "Ended", "Outcome", "Blocks" })
        {
            gridStoreJobs.Columns.Add(c, c);
        }

        foreach (var c in new[] { "Id", "Name", "Profile", "Blocks", "Errors" })
        {
            gridStorePrograms.Columns.Add(c, c);
        }

        foreach (var c in new[] { "Machine", "Station", "Job", "Program", "Line", "Blocks", "Outcome", "Lease" })
        {
            gridStoreShop.Columns.Add(c, c);
        }

        foreach (var grid in new[] { gridStoreJobs, gridStorePrograms, gridStoreShop })
        {
            grid.ReadOnly = true;
            grid.AllowUserToAddRows = false;
            grid.SelectionMode = DataGridViewSelectionMode.FullRowSelect;
            grid.MultiSelect = false;
        }

        btnStoreRefresh.Click += (_, _) => StoreRefreshRequested?.Invoke(this, EventArgs.Empty);
        btnStoreOpen.Click += (_, _) => OpenStoredProgramRequested?.Invoke(this, EventArgs.Empty);
        gridStorePrograms.CellDoubleClick += (_, e) =>
        {
            if (e.RowIndex >= 0)
            {
                OpenStoredProgramRequested?.Invoke(this, EventArgs.Empty);
            }
        };
        tabConsole.SelectedIndexChanged += (_, _) =>
        {
            if (tabConsole.SelectedTab == tabStore)
            {
                StoreRefreshRequested?.Invoke(this, EventArgs.Empty);
            }
        };
    }
}
