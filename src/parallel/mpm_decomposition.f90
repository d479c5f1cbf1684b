!> Slabs of the grid, one per image, cut across the longest axis of the domain.
!>
!> Image i owns the cells [cuts(i-1), cuts(i)) along the cut axis and the particles in them.
!> Its grid is the slab plus one ghost cell on each side that has a neighbour: a particle
!> of the slab touches the nodes of the ghost cells (cpGIMP) and, moving less than a cell in
!> a step (the blow-up guard stops a run that does not), stays on the image's grid until it
!> migrates at the end of the step. The three node layers around a cut are on both images;
!> their nodal sums are completed by the halo exchange (mpm_halo). The cuts balance the
!> particle count of the initial state.
module mpm_decomposition
    use mpm_kinds, only: wp, i8
    use mpm_strings, only: int_text
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_case, only: case_type
    implicit none
    private
    public :: decomposition_type, cut_axis, new_decomposition, local_case, global_cell, &
        min_slab_cells, image_grids

    integer, parameter :: min_slab_cells = 3
        !! fewest cells of a slab: the node layers of a cut are then shared by two images only

    !> How the grid is cut among the images, and this image's part.
    type :: decomposition_type
        integer :: images = 1
            !! number of images
        integer :: me = 1
            !! this image
        integer :: axis = 0
            !! cut axis (0: one image, nothing cut)
        integer, allocatable :: cuts(:)
            !! (0:images) first cell of each slab along the axis; cuts(images) = cells
        integer :: left = 0
            !! image on the low side, 0 for none
        integer :: right = 0
            !! image on the high side, 0 for none
        integer :: cell_lo = 0
            !! first cell of this image's slab (global, 0-based, along the axis)
        integer :: cell_hi = 0
            !! one past the last cell of the slab
        integer :: node_lo = 0
            !! global node layer of the first node layer of this image's grid
    end type decomposition_type

contains

    !> The axis with the most cells (the first of equals): the longest slabs are cut.
    pure integer function cut_axis(case)
        type(case_type), intent(in) :: case
            !! resolved case
        cut_axis = maxloc(case%domain%ncells(1:case%dim), dim=1)
    end function cut_axis

    !> Cell (0-based, along axis a) of a coordinate in the whole grid, clamped to the grid.
    pure integer function global_cell(case, x, a)
        type(case_type), intent(in) :: case
            !! resolved case
        real(wp), intent(in) :: x
            !! coordinate [m]
        integer, intent(in) :: a
            !! axis
        global_cell = min(max(int((x - case%domain%origin(a))/case%domain%dx), 0), case%domain%ncells(a) - 1)
    end function global_cell

    !> Cut the grid of a case into `images` slabs across `cut_axis(case)` with about the same
    !> number of particles each (`histogram`: particles per cell layer along that axis).
    subroutine new_decomposition(dec, case, images, me, histogram, error)
        type(decomposition_type), intent(out) :: dec
            !! the decomposition
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: images
            !! number of images
        integer, intent(in) :: me
            !! this image
        integer(i8), intent(in) :: histogram(0:)
            !! particles per cell layer along the cut axis
        type(error_type), allocatable, intent(out) :: error
            !! set when the grid has too few cells for the images

        integer :: k, c, cells
        integer(i8) :: total, below
        real(wp) :: target
        character(len=1), parameter :: names(3) = ["x", "y", "z"]

        dec%images = images
        dec%me = me
        if (images == 1) then
            dec%axis = 0
            dec%cuts = [0, 1]
            dec%cell_lo = 0
            dec%cell_hi = huge(1)
            dec%node_lo = 0
            return
        end if
        dec%axis = cut_axis(case)
        cells = case%domain%ncells(dec%axis)
        if (cells < min_slab_cells*images) then
            call fatal_error(error, case%file//": "//int_text(images)//" images need at "// &
                "least "//int_text(min_slab_cells*images)//" cells along the longest axis ("// &
                names(dec%axis)//", "//int_text(cells)//" cells; each image takes a slab of "// &
                int_text(min_slab_cells)//" cells or more): run on fewer images or refine "// &
                "domain.dx", exit_input)
            return
        end if
        allocate (dec%cuts(0:images))
        dec%cuts(0) = 0
        dec%cuts(images) = cells
        total = sum(histogram)
        c = 0
        below = 0
        do k = 1, images - 1
            if (total > 0) then
                target = real(total, wp)*real(k, wp)/real(images, wp)
                do while (c < cells .and. real(below, wp) < target)
                    below = below + histogram(c)
                    c = c + 1
                end do
                dec%cuts(k) = c
            else
                dec%cuts(k) = (cells*k)/images
            end if
            dec%cuts(k) = max(dec%cuts(k), dec%cuts(k - 1) + min_slab_cells)
            dec%cuts(k) = min(dec%cuts(k), cells - min_slab_cells*(images - k))
            if (dec%cuts(k) > c) then
                below = below + sum(histogram(c:dec%cuts(k) - 1))
                c = dec%cuts(k)
            else if (dec%cuts(k) < c) then
                below = below - sum(histogram(dec%cuts(k):c - 1))
                c = dec%cuts(k)
            end if
        end do
        call set_image(dec, me)
    end subroutine new_decomposition

    !> Make dec the decomposition as image k sees it (its slab and neighbours).
    pure subroutine set_image(dec, k)
        type(decomposition_type), intent(inout) :: dec
            !! a decomposition with its cuts
        integer, intent(in) :: k
            !! image

        dec%me = k
        dec%cell_lo = dec%cuts(k - 1)
        dec%cell_hi = dec%cuts(k)
        dec%left = merge(k - 1, 0, k > 1)
        dec%right = merge(k + 1, 0, k < dec%images)
        dec%node_lo = max(0, dec%cell_lo - 1)
    end subroutine set_image

    !> The case of this image's grid: its slab with the ghost cells; the faces at the cuts are
    !> free (the nodes there are completed by the halo exchange).
    function local_case(case, dec) result(local)
        type(case_type), intent(in) :: case
            !! resolved case (the whole grid)
        type(decomposition_type), intent(in) :: dec
            !! the decomposition
        type(case_type) :: local

        integer :: a, node_hi

        local = case
        if (dec%axis == 0) return
        a = dec%axis
        node_hi = min(case%domain%ncells(a), dec%cell_hi + 1)
        local%domain%origin(a) = case%domain%origin(a) + real(dec%node_lo, wp)*case%domain%dx
        local%domain%ncells(a) = node_hi - dec%node_lo
        if (dec%left > 0) call local%domain%set_free(1, a)
        if (dec%right > 0) call local%domain%set_free(2, a)
    end function local_case

    !> Origin and nodes per axis of the grid of every image (output index).
    subroutine image_grids(case, dec, origins, nns)
        type(case_type), intent(in) :: case
            !! resolved case (the whole grid)
        type(decomposition_type), intent(in) :: dec
            !! the decomposition (any image's)
        real(wp), allocatable, intent(out) :: origins(:, :)
            !! (3, images) position of node (0, 0, 0) of each image's grid [m]
        integer, allocatable, intent(out) :: nns(:, :)
            !! (3, images) nodes per axis of each image's grid (1 in z in 2D)

        type(decomposition_type) :: other
        type(case_type) :: local
        integer :: k

        allocate (origins(3, dec%images), nns(3, dec%images))
        do k = 1, dec%images
            other = dec
            if (dec%axis > 0) call set_image(other, k)
            local = local_case(case, other)
            origins(:, k) = local%domain%origin
            nns(:, k) = 1
            nns(1:case%dim, k) = local%domain%ncells(1:case%dim) + 1
        end do
    end subroutine image_grids

end module mpm_decomposition
